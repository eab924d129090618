// The carer's page: one HTML file, a section per page (#today, #reminders, ...), the JSON
// API (API.md) and live updates from /api/live. Everything from the server is put into the
// page with textContent, never as HTML, so a contact named "<script>" shows as that text.
'use strict';

let csrf = '';
const $ = (id) => document.getElementById(id);

function say(text, isError) {
  const m = $('message');
  m.textContent = text;
  m.classList.toggle('error', !!isError);
}

async function api(method, path, body, headers) {
  const options = {method, headers: Object.assign({}, headers || {})};
  if (method !== 'GET') options.headers['X-CSRF-Token'] = csrf;
  if (body !== undefined) {
    if (body instanceof Blob || body instanceof ArrayBuffer) {
      options.body = body;
    } else {
      options.headers['Content-Type'] = 'application/json';
      options.body = JSON.stringify(body);
    }
  }
  const response = await fetch(path, options);
  if (response.status === 401) {
    window.location.href = '/login.html';
    throw new Error('not logged in');
  }
  const data = await response.json();
  if (!response.ok) throw new Error(data.error || ('error ' + response.status));
  return data;
}

function cell(row, text) {
  const td = document.createElement('td');
  td.textContent = text;
  row.appendChild(td);
  return td;
}

function button(parent, label, onClick, secondary) {
  const b = document.createElement('button');
  b.type = 'button';
  b.textContent = label;
  if (secondary) b.className = 'secondary';
  b.addEventListener('click', onClick);
  parent.appendChild(b);
  parent.appendChild(document.createTextNode(' '));
  return b;
}

function item(list, text) {
  const li = document.createElement('li');
  li.textContent = text;
  list.appendChild(li);
  return li;
}

async function guarded(action, done) {
  try {
    await action();
    if (done) say(done);
  } catch (e) {
    say(e.message, true);
  }
}

// --- today ---------------------------------------------------------------------------
function showStatus(live) {
  $('light').textContent = live.running === false ? 'not running' : (live.light || 'off');
  $('doing').textContent = live.doing || 'nothing';
}

function addTurn(turn) {
  const list = $('turns');
  item(list, turn.who + ': ' + turn.text);
  while (list.children.length > 20) list.removeChild(list.firstChild);
}

function eventText(e) { return e.time + '  ' + e.kind + ' (' + e.source + '): ' + e.message; }

async function loadToday() {
  const s = await api('GET', '/api/status');
  showStatus(Object.assign({running: s.running}, s.live || {}));
  const reminders = $('today-reminders');
  reminders.replaceChildren();
  for (const r of s.next_reminders) item(reminders, r.next + '  ' + r.title + ' (' + r.repeat + ')');
  if (!s.next_reminders.length) item(reminders, 'No reminders.');
  $('turns').replaceChildren();
  for (const t of (s.live ? s.live.turns : [])) addTurn(t);
  const events = $('today-events');
  events.replaceChildren();
  for (const e of s.recent_events) item(events, eventText(e));
}

// --- reminders -----------------------------------------------------------------------
function resetReminderForm() {
  $('reminder-form').reset();
  $('reminder-id').value = '';
  $('reminder-save').textContent = 'Add reminder';
  $('reminder-cancel').classList.add('hidden');
}

async function loadReminders() {
  const body = $('reminders');
  body.replaceChildren();
  for (const r of await api('GET', '/api/reminders')) {
    const row = document.createElement('tr');
    cell(row, r.next);
    cell(row, r.title);
    cell(row, r.repeat);
    const actions = cell(row, '');
    button(actions, 'Edit', () => {
      $('reminder-id').value = r.id;
      $('reminder-title').value = r.title;
      $('reminder-at').value = r.next.replace(' ', 'T');
      $('reminder-save').textContent = 'Save reminder';
      $('reminder-cancel').classList.remove('hidden');
      $('reminder-title').focus();
    }, true).setAttribute('aria-label', 'Edit reminder ' + r.title);
    button(actions, 'Delete', () => guarded(async () => {
      await api('DELETE', '/api/reminders/' + r.id);
      await loadReminders();
    }, 'Reminder deleted.'), true).setAttribute('aria-label', 'Delete reminder ' + r.title);
    body.appendChild(row);
  }
}

$('reminder-cancel').addEventListener('click', resetReminderForm);
$('reminder-form').addEventListener('submit', (event) => {
  event.preventDefault();
  guarded(async () => {
    const id = $('reminder-id').value;
    const body = {title: $('reminder-title').value, at: $('reminder-at').value,
                  repeat: $('reminder-repeat').value};
    if ($('reminder-window').value) body.window = $('reminder-window').value;
    await api(id ? 'PUT' : 'POST', '/api/reminders' + (id ? '/' + id : ''), body);
    resetReminderForm();
    await loadReminders();
  }, 'Reminder saved.');
});

// --- contacts ------------------------------------------------------------------------
function resetContactForm() {
  $('contact-form').reset();
  $('contact-id').value = '';
  $('contact-save').textContent = 'Add contact';
  $('contact-cancel').classList.add('hidden');
}

async function loadContacts() {
  const body = $('contacts');
  body.replaceChildren();
  for (const c of await api('GET', '/api/contacts')) {
    const row = document.createElement('tr');
    cell(row, c.name);
    cell(row, c.relation);
    cell(row, c.phones.concat(c.sip).join(', '));
    cell(row, c.emergency ? '#' + c.emergency : '');
    const actions = cell(row, '');
    button(actions, 'Edit', () => {
      $('contact-id').value = c.id;
      $('contact-name').value = c.name;
      $('contact-relation').value = c.relation;
      $('contact-phone').value = c.phones[0] || '';
      $('contact-sip').value = c.sip[0] || '';
      $('contact-emergency').value = c.emergency;
      $('contact-save').textContent = 'Save contact';
      $('contact-cancel').classList.remove('hidden');
      $('contact-name').focus();
    }, true).setAttribute('aria-label', 'Edit contact ' + c.name);
    button(actions, 'Delete', () => guarded(async () => {
      await api('DELETE', '/api/contacts/' + c.id);
      await loadContacts();
    }, 'Contact deleted.'), true).setAttribute('aria-label', 'Delete contact ' + c.name);
    body.appendChild(row);
  }
}

$('contact-cancel').addEventListener('click', resetContactForm);
$('contact-form').addEventListener('submit', (event) => {
  event.preventDefault();
  guarded(async () => {
    const id = $('contact-id').value;
    const body = {name: $('contact-name').value, relation: $('contact-relation').value,
                  phones: [$('contact-phone').value], sip: [$('contact-sip').value],
                  emergency: parseInt($('contact-emergency').value || '0', 10)};
    await api(id ? 'PUT' : 'POST', '/api/contacts' + (id ? '/' + id : ''), body);
    resetContactForm();
    await loadContacts();
  }, 'Contact saved.');
});

// --- skills --------------------------------------------------------------------------
async function loadSkills() {
  const body = $('skills');
  body.replaceChildren();
  for (const s of await api('GET', '/api/skills')) {
    const row = document.createElement('tr');
    cell(row, s.id);
    cell(row, s.version + (s.previous ? ' (previous ' + s.previous + ')' : ''));
    cell(row, s.permissions.join(', ') || 'none');
    const actions = cell(row, '');
    if (s.previous) {
      button(actions, 'Roll back', () => guarded(async () => {
        await api('POST', '/api/skills/' + encodeURIComponent(s.id) + '/rollback');
        await loadSkills();
      }, 'Rolled back ' + s.id + '.'), true).setAttribute('aria-label', 'Roll back ' + s.id);
    }
    button(actions, 'Remove', () => guarded(async () => {
      await api('DELETE', '/api/skills/' + encodeURIComponent(s.id));
      await loadSkills();
    }, 'Removed ' + s.id + '.'), true).setAttribute('aria-label', 'Remove ' + s.id);
    body.appendChild(row);
  }
}

$('skill-form').addEventListener('submit', (event) => {
  event.preventDefault();
  guarded(async () => {
    const pkg = $('skill-package').files[0];
    const sig = $('skill-signature').files[0];
    const signature = btoa(String.fromCharCode(...new Uint8Array(await sig.arrayBuffer())));
    const query = '?file=' + encodeURIComponent(pkg.name) + ($('skill-approve').checked ? '&approve=1' : '');
    const result = await api('POST', '/api/skills/install' + query, pkg,
                             {'X-Marvin-Signature': signature, 'Content-Type': 'application/octet-stream'});
    $('skill-form').reset();
    await loadSkills();
    say(result.outcome + ' ' + result.id + ' ' + result.version + '.');
  });
});

// --- events --------------------------------------------------------------------------
function eventRow(e) {
  const row = document.createElement('tr');
  cell(row, e.time);
  cell(row, e.kind);
  cell(row, e.source);
  cell(row, e.message);
  return row;
}

async function loadEvents() {
  const body = $('events');
  body.replaceChildren();
  for (const e of await api('GET', '/api/events?limit=100')) body.appendChild(eventRow(e));
}

// --- pages and live updates ----------------------------------------------------------
const pages = {today: loadToday, reminders: loadReminders, contacts: loadContacts,
               skills: loadSkills, events: loadEvents};

function currentPage() {
  const name = window.location.hash.slice(1);
  return pages[name] ? name : 'today';
}

function showPage() {
  const name = currentPage();
  for (const p of Object.keys(pages)) {
    $('page-' + p).classList.toggle('hidden', p !== name);
    const link = document.querySelector('nav a[href="#' + p + '"]');
    if (p === name) link.setAttribute('aria-current', 'page'); else link.removeAttribute('aria-current');
  }
  guarded(pages[name]);
}

function startLive() {
  const live = new EventSource('/api/live');
  live.addEventListener('hello', (m) => {
    const s = JSON.parse(m.data);
    showStatus(s);
  });
  live.addEventListener('status', (m) => showStatus(JSON.parse(m.data)));
  live.addEventListener('turn', (m) => addTurn(JSON.parse(m.data)));
  live.addEventListener('event', (m) => {
    const e = JSON.parse(m.data);
    $('events').prepend(eventRow(e));
    const today = $('today-events');
    const li = document.createElement('li');
    li.textContent = eventText(e);
    today.prepend(li);
  });
  live.addEventListener('changed', (m) => {
    const what = JSON.parse(m.data).what;
    if (what === currentPage() || currentPage() === 'today') guarded(pages[currentPage()]);
  });
}

$('logout').addEventListener('click', () => guarded(async () => {
  await api('POST', '/api/logout');
  window.location.href = '/login.html';
}));

window.addEventListener('hashchange', showPage);
(async () => {
  try {
    csrf = (await api('GET', '/api/session')).csrf;
  } catch (e) {
    return;
  }
  showPage();
  startLive();
})();
