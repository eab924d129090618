// The carer's web page in a real browser: Debian's chromium, headless, driven by
// puppeteer-core, against `marvin run --sim` serving its page on an ephemeral port.
// Logs in, adds a reminder and finds it in `marvin schedule list`, edits it, sees the home
// map with the robot on it, installs a signed skill package, sees the skill's error event
// appear live, logs out.
//
// Usage: node browser_test.mjs MARVIN_EXE PUPPETEER_DIR GROUP_PHOTO (a photo of several people)
// Exit 0: passed; 77: skipped (no chromium or no puppeteer-core, named on stderr); 1: failed.
import {spawn, execFileSync} from 'node:child_process';
import {createRequire} from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';

const [marvin, puppeteerDir, groupPhoto] = process.argv.slice(2);
const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
if (!fs.existsSync(chromium)) {
  console.error(`skipped: no chromium at ${chromium} (apt-get install chromium)`);
  process.exit(77);
}
if (!fs.existsSync(path.join(puppeteerDir, 'node_modules', 'puppeteer-core'))) {
  console.error(`skipped: no puppeteer-core in ${puppeteerDir} (run scripts/fetch-web-test-deps)`);
  process.exit(77);
}
const puppeteer = createRequire(path.resolve(puppeteerDir, 'package.json'))('puppeteer-core');

const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'marvin-web-browser-'));
const dataDir = path.join(tmp, 'data');
const skillsDir = path.join(tmp, 'skills');
const env = Object.assign({}, process.env, {MARVIN_DATA_DIR: dataDir, MARVIN_SKILLS_DIR: skillsDir});
const password = 'carer password 1';
let host;
let browser;

function check(condition, what) {
  if (!condition) throw new Error('check failed: ' + what);
  console.log('ok: ' + what);
}

function run(args, input) {
  return execFileSync(marvin, args, {env, input, encoding: 'utf8'});
}

let hostOut = '';  // everything the host printed

// Resolves with the first match of `pattern` in the host's output.
function hostSays(pattern, what) {
  return new Promise((resolve, reject) => {
    const look = () => {
      const m = hostOut.match(pattern);
      if (!m) return false;
      clearTimeout(timer);
      host.stdout.off('data', look);
      resolve(m);
      return true;
    };
    const timer = setTimeout(() => {
      host.stdout.off('data', look);
      reject(new Error(what + '; the host printed:\n' + hostOut));
    }, 60000);
    if (!look()) host.stdout.on('data', look);
  });
}

function startHost() {
  host = spawn(marvin, ['run', '--sim', '--web-listen', '127.0.0.1:0'], {env});
  host.stdout.setEncoding('utf8');
  host.stderr.setEncoding('utf8');
  host.stdout.on('data', (d) => { hostOut += d; });
  host.stderr.on('data', (d) => process.stderr.write('[host stderr] ' + d));
  host.on('exit', (code) => { hostOut += '\n(exited with ' + code + ')'; });
  return hostSays(/\[web page: (https:\/\/[^\]]+)\]/, 'the host did not serve its page').then((m) => m[1]);
}

async function main() {
  // The carer's password, and a skills folder trusting a key of ours.
  run(['web', 'password', '--data-dir', dataDir], password + '\n');
  execFileSync('minisign', ['-G', '-W', '-p', path.join(tmp, 'key.pub'), '-s', path.join(tmp, 'key.sec')]);
  run(['skill', 'repo-add', 'home', path.join(tmp, 'repo'), '--key', path.join(tmp, 'key.pub'),
       '--skills-dir', skillsDir]);
  // A skill whose intent fails: saying "boom test" records a skill_error event.
  const src = path.join(tmp, 'boom');
  fs.mkdirSync(src);
  fs.writeFileSync(path.join(src, 'skill.json'), JSON.stringify({
    id: 'boom', name: 'boom', version: '1.0.0', kind: 'lua', host_api: {min: '1.0'},
    permissions: ['storage'], intents: [{name: 'greet', templates: ['boom test']}]}));
  fs.writeFileSync(path.join(src, 'main.lua'), 'marvin.on("greet", function() error("boom on purpose") end)\n');
  const pkg = path.join(tmp, 'boom-1.0.0.mskill');
  run(['skill', 'pack', src, '--sign', path.join(tmp, 'key.sec'), '-o', pkg]);

  const url = await startHost();
  // Trust exactly the certificate Marvin made on first start (its public key's hash).
  const spki = execFileSync('sh', ['-c',
    'openssl x509 -in "$1" -pubkey -noout | openssl pkey -pubin -outform der | ' +
    'openssl dgst -sha256 -binary | base64', 'sh', path.join(dataDir, 'web', 'cert.pem')],
    {encoding: 'utf8'}).trim();
  browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage',
           '--ignore-certificate-errors-spki-list=' + spki],
  });
  const page = await browser.newPage();
  page.setDefaultTimeout(20000);
  page.on('pageerror', (e) => console.error('[page error] ' + e.message));

  // Log in: the page sends us to the login page first.
  await page.goto(url);
  check(page.url().endsWith('/login.html'), 'without a session the page is the login page');
  await page.type('#password', 'wrong password');
  await page.click('button[type=submit]');
  await page.waitForFunction(() => document.getElementById('login-message').textContent === 'wrong password');
  check(true, 'a wrong password is refused with "wrong password"');
  await page.$eval('#password', (e) => { e.value = ''; });
  await page.type('#password', password);
  await Promise.all([page.waitForNavigation(), page.click('button[type=submit]')]);
  await page.waitForFunction(() => document.getElementById('light').textContent.startsWith('awaiting'));
  check(true, 'logged in: Today shows the status light "awaiting"');

  // A reminder added on the page is in `marvin schedule list`.
  await page.goto(url + '#reminders');
  await page.type('#reminder-title', 'water the plants');
  await page.$eval('#reminder-at', (e) => { e.value = '2031-05-06T07:30'; });
  await page.select('#reminder-repeat', 'daily');
  await page.click('#reminder-save');
  await page.waitForFunction(() => document.getElementById('reminders').textContent.includes('water the plants'));
  const listed = run(['schedule', 'list', '--data-dir', dataDir]);
  check(/2031-05-06 07:30\s+daily\s+water the plants/.test(listed), '`marvin schedule list` shows the reminder: ' + listed.trim());

  // Edited on the page: the form starts from what is stored (its repeat too).
  await page.click('button[aria-label="Edit reminder water the plants"]');
  check(await page.$eval('#reminder-repeat', (e) => e.value) === 'daily', 'the edit form starts with the stored repeat');
  await page.$eval('#reminder-title', (e) => { e.value = ''; });
  await page.type('#reminder-title', 'water the orchids');
  await page.click('#reminder-save');
  await page.waitForFunction(() => document.getElementById('reminders').textContent.includes('water the orchids'));
  const edited = run(['schedule', 'list', '--data-dir', dataDir]);
  check(/2031-05-06 07:30\s+daily\s+water the orchids/.test(edited) && !edited.includes('water the plants'),
        '`marvin schedule list` shows the edited reminder only: ' + edited.trim());

  // The home: the simulated world's floor plan with the robot in its room.
  await page.goto(url + '#home');
  await page.waitForFunction(() => document.getElementById('robot-where').textContent.startsWith('Marvin is in the'));
  const where = await page.$eval('#robot-where', (e) => e.textContent);
  const rooms = await page.$$eval('#home-map polygon.room', (es) => es.length);
  check(rooms > 0 && await page.$('#home-map circle.robot') !== null,
        'the home page draws ' + rooms + ' rooms and the robot: "' + where + '"');

  // People: a group photo is refused with the CLI's rule, named on the page.
  await page.goto(url + '#people');
  await page.type('#enrol-name', 'Bob');
  await (await page.$('#enrol-photos')).uploadFile(groupPhoto);
  await page.click('#enrol-save');
  await page.waitForFunction(() => document.getElementById('message').textContent.includes('faces; give photos of Bob alone'));
  check(run(['people', 'list', '--data-dir', dataDir]).trim() === '',
        'a group photo uploaded on the People page is refused: "' + await page.$eval('#message', (e) => e.textContent) + '"');

  // A contact named with markup is shown as text.
  await page.goto(url + '#contacts');
  await page.type('#contact-name', '<img src=x onerror=alert(1)>Anna');
  await page.click('#contact-save');
  await page.waitForFunction(() => document.getElementById('contacts').textContent.includes('<img src=x'));
  check(await page.$('#contacts img') === null, 'a contact named <img ...> is shown as text, not markup');

  // Install the signed package by upload.
  await page.goto(url + '#skills');
  const [pkgInput] = await Promise.all([page.$('#skill-package')]);
  await pkgInput.uploadFile(pkg);
  await (await page.$('#skill-signature')).uploadFile(pkg + '.minisig');
  await page.click('#skill-approve');
  await page.click('#skill-install');
  await page.waitForFunction(() => document.getElementById('skills').textContent.includes('boom'));
  check(run(['skill', 'list', '--skills-dir', skillsDir]).includes('boom 1.0.0'), 'the uploaded skill is installed (marvin skill list)');

  // The host reloads it; saying its sentence makes it fail: the event appears live.
  await page.goto(url + '#events');
  await hostSays(/\[skill boom 1\.0\.0[^\]]*\]/, 'the host did not load the installed skill');
  const before = Date.now();
  host.stdin.write('boom test\n');
  await page.waitForFunction(() => document.getElementById('events').textContent.includes('boom on purpose'));
  check(true, 'the skill_error event appeared live on the events page (' + (Date.now() - before) + ' ms after the request)');

  // Log out: the session is gone.
  await Promise.all([page.waitForNavigation(), page.click('#logout')]);
  check(page.url().endsWith('/login.html'), 'logged out: back at the login page');
  const status = await page.evaluate(async () => (await fetch('/api/status')).status);
  check(status === 401, 'after logging out the API answers 401');
}

let failed = false;
try {
  await main();
} catch (e) {
  console.error(e.stack || String(e));
  failed = true;
} finally {
  if (browser) await browser.close();
  if (host) {
    host.stdin.end();
    host.kill('SIGTERM');
  }
  fs.rmSync(tmp, {recursive: true, force: true});
}
process.exit(failed ? 1 : 0);
