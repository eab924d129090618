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
      const repeat = $('reminder-repeat');
      if (![...repeat.options].some((o) => o.value === r.repeat_spec)) {
        const option = document.createElement('option');
        option.value = r.repeat_spec;
        option.textContent = r.repeat;
        repeat.appendChild(option);
      }
      repeat.value = r.repeat_spec;
      $('reminder-window').value = r.window;
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
  const message = cell(row, e.message);
  if (e.photo) {
    // The intruder alert's photo, asked by the event's id (the session's cookie goes along).
    const link = document.createElement('a');
    link.href = '/api/events/' + e.id + '/photo';
    const img = document.createElement('img');
    img.src = link.href;
    img.className = 'event-photo';
    img.alt = 'Photo taken at the intruder alert of ' + e.time;
    link.appendChild(img);
    message.appendChild(document.createElement('br'));
    message.appendChild(link);
  }
  return row;
}

async function loadEvents() {
  const body = $('events');
  body.replaceChildren();
  for (const e of await api('GET', '/api/events?limit=100')) body.appendChild(eventRow(e));
}

// --- people --------------------------------------------------------------------------
function resetPersonForm() {
  $('person-form').reset();
  $('person-id').value = '';
  $('person-form').classList.add('hidden');
}

async function loadPeople() {
  const body = $('people');
  body.replaceChildren();
  const people = await api('GET', '/api/people');
  for (const p of people) {
    const row = document.createElement('tr');
    cell(row, p.name);
    cell(row, String(p.faces));
    cell(row, p.enrolled ? p.enrolled + ' (' + p.enrolled_by + ')' : '');
    const actions = cell(row, '');
    button(actions, 'Rename', () => {
      $('person-id').value = p.id;
      $('person-old').textContent = p.name;
      $('person-name').value = p.name;
      $('person-form').classList.remove('hidden');
      $('person-name').focus();
    }, true).setAttribute('aria-label', 'Rename ' + p.name);
    button(actions, 'Forget', () => guarded(async () => {
      if (!window.confirm('Forget ' + p.name + ' and their faces?')) return;
      await api('DELETE', '/api/people/' + p.id);
      await loadPeople();
    }, 'Forgot ' + p.name + '.'), true).setAttribute('aria-label', 'Forget ' + p.name);
    body.appendChild(row);
  }
  if (!people.length) cell(body.appendChild(document.createElement('tr')), 'Nobody yet.');
}

$('enrol-form').addEventListener('submit', (event) => {
  event.preventDefault();
  guarded(async () => {
    const name = $('enrol-name').value;
    let result;
    // One photo per request: a refused photo names itself, the ones before it stay learnt.
    for (const photo of $('enrol-photos').files) {
      result = await api('POST', '/api/people/enroll?name=' + encodeURIComponent(name) +
                         '&file=' + encodeURIComponent(photo.name), photo,
                         {'Content-Type': 'application/octet-stream'});
    }
    $('enrol-form').reset();
    await loadPeople();
    say('Marvin knows ' + result.name + ' from ' + result.faces + ' photo' +
        (result.faces === 1 ? '' : 's') + '.');
  });
});

$('person-cancel').addEventListener('click', resetPersonForm);
$('person-form').addEventListener('submit', (event) => {
  event.preventDefault();
  guarded(async () => {
    await api('PUT', '/api/people/' + $('person-id').value, {name: $('person-name').value});
    resetPersonForm();
    await loadPeople();
  }, 'Renamed.');
});

// --- devices -------------------------------------------------------------------------
function deviceState(d) {
  if (!d.available) return 'offline';
  if (d.on === null) return 'unknown';
  if (d.type === 'thermostat') {
    return (d.on ? 'heating' : 'off') +
        (d.target_temperature !== null ? ', set to ' + d.target_temperature + ' °C' : '') +
        (d.temperature !== null ? ', ' + d.temperature + ' °C in the room' : '');
  }
  return (d.on ? 'on' : 'off') + (d.on && d.brightness !== null ? ' ' + d.brightness + '%' : '');
}

async function loadDevices() {
  const home = await api('GET', '/api/devices');
  $('devices-state').textContent = !home.configured ? 'Marvin has no smart home here.'
      : home.connected ? 'Connected to the home\'s devices.'
      : 'The home\'s broker cannot be reached; the states may be old.';
  const body = $('devices');
  body.replaceChildren();
  for (const d of home.devices) {
    const row = document.createElement('tr');
    cell(row, d.name);
    cell(row, d.room);
    cell(row, deviceState(d));
    const actions = cell(row, '');
    for (const on of [true, false]) {
      const label = on ? 'Switch on' : 'Switch off';
      button(actions, label, () => guarded(async () => {
        say('Switching the ' + d.name + (on ? ' on' : ' off') + '…');
        await api('POST', '/api/devices/' + encodeURIComponent(d.id), {on});
        await loadDevices();
      }, 'The ' + d.name + ' is ' + (on ? 'on' : 'off') + '.'), !on)
          .setAttribute('aria-label', label + ' ' + d.name);
    }
    if (d.dimmable) {
      // Dimming: a labelled number input (keyboard and screen readers) and a Set button.
      const id = 'dim-' + d.id.replace(/[^A-Za-z0-9_-]/g, '_');
      const label = document.createElement('label');
      label.htmlFor = id;
      label.textContent = 'Brightness of the ' + d.name + ' (%) ';
      const input = document.createElement('input');
      input.type = 'number';
      input.id = id;
      input.min = '0';
      input.max = '100';
      input.step = '1';
      input.value = d.brightness === null ? '' : String(d.brightness);
      actions.appendChild(label);
      actions.appendChild(input);
      actions.appendChild(document.createTextNode(' '));
      button(actions, 'Set', () => guarded(async () => {
        const brightness = Number(input.value);
        if (input.value === '' || !Number.isInteger(brightness) || brightness < 0 || brightness > 100) {
          throw new Error('Brightness: a whole number from 0 to 100.');
        }
        say('Dimming the ' + d.name + ' to ' + brightness + '%…');
        // 0 % is off (a lamp switched off need not report a brightness of 0).
        await api('POST', '/api/devices/' + encodeURIComponent(d.id),
                  brightness > 0 ? {on: true, brightness} : {on: false});
        await loadDevices();
        say('The ' + d.name + (brightness > 0 ? ' is at ' + brightness + '%.' : ' is off.'));
      }), true)
          .setAttribute('aria-label', 'Set the brightness of the ' + d.name);
    }
    body.appendChild(row);
  }
}

// --- the home map --------------------------------------------------------------------
const SVG = 'http://www.w3.org/2000/svg';
function shape(parent, name, attributes, text) {
  const e = document.createElementNS(SVG, name);
  for (const [k, v] of Object.entries(attributes)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  parent.appendChild(e);
  return e;
}

async function loadHome() {
  const h = await api('GET', '/api/home');
  const where = h.robot ? (h.robot.room ? 'Marvin is in the ' + h.robot.room + '.'
                                        : 'Marvin is between rooms.')
                        : 'Where Marvin is is not known here.';
  $('robot-where').textContent = where;
  const svg = $('home-map');
  const title = $('home-map-title');
  svg.replaceChildren(title);
  svg.classList.toggle('hidden', !h.map);
  const rooms = $('home-rooms');
  rooms.replaceChildren();
  if (h.map) {
    const [[x0, y0], [x1, y1]] = h.map.bounds;
    const m = 0.3;
    svg.setAttribute('viewBox', [x0 - m, -(y1 + m), x1 - x0 + 2 * m, y1 - y0 + 2 * m].join(' '));
    const pt = (p) => p[0] + ',' + (-p[1]);  // the world's y grows up, the picture's down
    for (const r of h.map.rooms) shape(svg, 'polygon', {class: 'room', points: r.outline.map(pt).join(' ')});
    for (const f of h.map.furniture) {
      shape(svg, 'rect', {class: 'furniture', x: f.min[0], y: -f.max[1],
                          width: f.max[0] - f.min[0], height: f.max[1] - f.min[1]});
    }
    for (const w of h.map.walls) {
      shape(svg, 'line', {class: 'wall', x1: w[0][0], y1: -w[0][1], x2: w[1][0], y2: -w[1][1]});
    }
    for (const r of h.map.rooms) {
      shape(svg, 'text', {class: 'label', x: r.spot[0], y: -r.spot[1], 'text-anchor': 'middle'}, r.name);
      const places = h.map.places.filter((p) => p.room === r.name).map((p) => p.name);
      item(rooms, r.name + (places.length ? ': ' + places.join(', ') : ''));
    }
    if (h.robot) {
      const [x, y] = h.robot.at;
      const a = h.robot.heading_deg * Math.PI / 180;
      shape(svg, 'circle', {class: 'robot', cx: x, cy: -y, r: 0.18});
      shape(svg, 'line', {class: 'wall', x1: x, y1: -y,
                          x2: x + 0.3 * Math.cos(a), y2: -(y + 0.3 * Math.sin(a))});
      title.textContent = 'Floor plan of the home. ' + where;
    }
  } else {
    item(rooms, 'No floor plan here: Marvin runs without a world file.');
  }
  const body = $('sightings');
  body.replaceChildren();
  for (const s of h.sightings) {
    const row = document.createElement('tr');
    cell(row, s.what);
    cell(row, [s.room, s.near ? 'near the ' + s.near : ''].filter(Boolean).join(', ') || 'unknown');
    cell(row, s.seen);
    body.appendChild(row);
  }
  if (!h.sightings.length) cell(body.appendChild(document.createElement('tr')), 'Nothing seen yet.');
}

// --- pages and live updates ----------------------------------------------------------
const pages = {today: loadToday, reminders: loadReminders, contacts: loadContacts,
               skills: loadSkills, events: loadEvents, people: loadPeople,
               devices: loadDevices, home: loadHome};

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
  live.addEventListener('status', (m) => {
    showStatus(JSON.parse(m.data));
    // The robot moved or turned: the map shows where it is now.
    if (currentPage() === 'home') guarded(loadHome);
  });
  live.addEventListener('turn', (m) => addTurn(JSON.parse(m.data)));
  live.addEventListener('event', (m) => {
    const e = JSON.parse(m.data);
    $('events').prepend(eventRow(e));
    const today = $('today-events');
    const li = document.createElement('li');
    li.textContent = eventText(e);
    today.prepend(li);
    // A face learnt or forgotten by voice or on the robot shows on the people page.
    if (e.kind.startsWith('face_') && currentPage() === 'people') guarded(loadPeople);
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
