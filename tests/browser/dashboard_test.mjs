// The dashboard in a real browser (Debian's headless Chromium, driven by playwright-core):
// a scheduler with a token and its HTTP side on loopback, a shot submitted, the page opened
// without the token (it asks), pause and resume, the progress seen moving once a worker
// starts, the thumbnails, a done frame requeued and rendered again, a priority changed, a
// screenshot, and a link carrying the token (as `pathfarm local --http` logs it).
// Everything talks to 127.0.0.1 only; every wait has a deadline, and every process started
// here is killed when the script ends, however it ends.
//
// node dashboard_test.mjs --pathfarm BIN --source DIR --work DIR --screenshot PNG
import { spawn, execFileSync } from 'node:child_process';
import { existsSync, readFileSync, writeFileSync, mkdirSync, openSync } from 'node:fs';
import { join } from 'node:path';
import { parseArgs } from 'node:util';
import { chromium } from 'playwright-core';

const { values: args } = parseArgs({
  options: {
    pathfarm: { type: 'string' },
    source: { type: 'string' },
    work: { type: 'string' },
    screenshot: { type: 'string' },
    chromium: { type: 'string', default: '/usr/bin/chromium' },
  },
});
const TOKEN = 'browser-test-token';
const FRAMES = 8;
const started = Date.now();

// ---- processes --------------------------------------------------------------------------

// The test decides who carries the token: nothing is inherited from the caller.
const baseEnv = { ...process.env };
delete baseEnv.PATHFARM_TOKEN;
delete baseEnv.PATHFARM_TOKEN_FILE;

const children = [];
function start(name, argv, env = {}) {
  const log = openSync(join(args.work, name + '.log'), 'w');
  const child = spawn(argv[0], argv.slice(1), { stdio: ['ignore', log, log], env: { ...baseEnv, ...env } });
  children.push({ name, child });
  return child;
}
function stopAll() {
  for (const { child } of children) if (child.exitCode === null && child.signalCode === null) child.kill('SIGKILL');
}
process.on('exit', stopAll);
for (const signal of ['SIGINT', 'SIGTERM']) process.on(signal, () => process.exit(1));

function log(message) {
  console.log(`[${((Date.now() - started) / 1000).toFixed(1)} s] ${message}`);
}

async function waitFor(what, condition, timeoutMs = 20000, pollMs = 100) {
  const deadline = Date.now() + timeoutMs;
  for (;;) {
    const value = await condition();
    if (value) return value;
    if (Date.now() > deadline) throw new Error(`timed out after ${timeoutMs} ms waiting for ${what}`);
    await new Promise((resolve) => setTimeout(resolve, pollMs));
  }
}

function readPort(file) {
  return existsSync(file) ? Number(readFileSync(file, 'utf8').trim()) || 0 : 0;
}

// ---- the farm ---------------------------------------------------------------------------

mkdirSync(args.work, { recursive: true });
const tokenFile = join(args.work, 'token');
writeFileSync(tokenFile, TOKEN + '\n');
const tokenEnv = { PATHFARM_TOKEN_FILE: tokenFile };

start('scheduler', [args.pathfarm, 'scheduler', '--listen', '127.0.0.1:0', '--port-file', join(args.work, 'port'),
  '--http', '127.0.0.1:0', '--http-port-file', join(args.work, 'http-port'), '--db', join(args.work, 'farm.db'),
  '--store', join(args.work, 'store'), '--token-file', tokenFile]);
const grpcPort = await waitFor('the scheduler\'s port', () => readPort(join(args.work, 'port')));
const httpPort = await waitFor('the scheduler\'s HTTP port', () => readPort(join(args.work, 'http-port')));
const scheduler = `127.0.0.1:${grpcPort}`;
const dashboard = `http://127.0.0.1:${httpPort}/`;
log(`scheduler on ${scheduler}, dashboard on ${dashboard}`);

// A small shot with enough frames for its progress to be seen moving.
const shotFile = join(args.work, 'browser.shot.json');
writeFileSync(shotFile, JSON.stringify({
  name: 'browser-shot',
  scene: join(args.source, 'scenes', 'cornell', 'scene.json'),
  frames: { start: 0, end: FRAMES - 1 },
  resolution: [128, 96],
  spp: 8,
  max_depth: 4,
  pipeline: 'pt',
  tile: 32,
  output: join(args.work, 'output'),
}));
const submitted = execFileSync(args.pathfarm, ['submit', shotFile, '--scheduler', scheduler],
  { env: { ...baseEnv, ...tokenEnv }, encoding: 'utf8', timeout: 20000 });
const shotId = Number(submitted.trim().split('\n').filter((line) => /^\d+$/.test(line)).pop());
log(`shot ${shotId} submitted`);

// ---- the browser ------------------------------------------------------------------------

const browser = await chromium.launch({
  executablePath: args.chromium,
  headless: true,
  timeout: 20000,
  // Nothing but loopback resolves, whatever Chromium would like to call home to.
  args: ['--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1', '--no-first-run', '--disable-component-update'],
});
const failures = [];
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 1000 } });
  await context.route('**/*', (route) =>
    new URL(route.request().url()).hostname === '127.0.0.1' ? route.continue() : route.abort());
  const page = await context.newPage();
  page.setDefaultTimeout(15000);
  page.on('pageerror', (error) => failures.push('page error: ' + error.message));
  page.on('console', (message) => { if (message.type() === 'error') log('browser console: ' + message.text()); });

  // Without the token the page loads, and asks for it.
  await page.goto(dashboard);
  await page.waitForSelector('#token-form:not([hidden])');
  log('the page asks for the token');
  await page.fill('#token-input', TOKEN);
  await page.click('#token-form button[type=submit]');
  const row = page.locator('tr', { hasText: 'browser-shot' });
  await row.waitFor();
  const tasksText = async () => (await row.locator('.progress').first().innerText()).trim();
  const total = Number((await tasksText()).match(/\/ (\d+)/)[1]);
  log(`shots table: ${await tasksText()}`);

  // The shot's page: pause, then resume. This happens before any worker runs: a fast
  // worker could otherwise finish the shot before the click, and a done shot stays done.
  await row.click();
  await page.locator('.shot-header h1').waitFor();
  await page.click('button:text-is("Pause")');
  await page.locator('.shot-header .badge', { hasText: 'paused' }).waitFor();
  log('paused');
  await page.click('button:text-is("Resume")');
  await page.locator('.shot-header .badge', { hasText: 'queued' }).waitFor();
  log('resumed');
  await page.click('a:text-is("\u2190 all shots")');
  await row.waitFor();

  // The worker starts: the progress moves while the page watches.
  start('worker', [args.pathfarm, 'worker', '--scheduler', scheduler, '--threads', '1', '--name', 'browser-worker',
    '--cache', join(args.work, 'cache')], tokenEnv);
  const seen = new Set();
  await waitFor('the progress to move in the shots table', async () => {
    const done = Number((await tasksText()).split(' ')[0]);
    seen.add(done);
    return done > 0 && done < total && seen.size >= 2;
  }, 30000, 50);
  log(`progress seen moving: ${[...seen].sort((a, b) => a - b).join(', ')} of ${total} tasks`);
  const farmScreenshot = args.screenshot.replace(/\.png$/, '-farm.png');
  await page.screenshot({ path: farmScreenshot });
  log(`screenshot of the farm: ${farmScreenshot}`);

  // Back on the shot's page, to watch it finish.
  await row.click();
  await page.locator('.shot-header h1').waitFor();

  // Done: every frame has its thumbnail, at the frame's size (it fits 160 pixels).
  await page.locator('.shot-header .badge', { hasText: 'done' }).waitFor({ timeout: 60000 });
  log('the shot is done');
  const thumbnails = page.locator('.frames img');
  await waitFor(`${FRAMES} thumbnails`, async () => (await thumbnails.count()) === FRAMES);
  const sizes = await thumbnails.evaluateAll((images) => images.map((i) => i.complete && `${i.naturalWidth}x${i.naturalHeight}`));
  if (!sizes.every((s) => s === '128x96')) failures.push('thumbnail sizes: ' + sizes.join(', '));
  log(`thumbnails: ${sizes.length} of ${sizes[0]}`);

  // A done frame requeued runs again: the shot is active, frame 3's tiles render anew.
  const frameThree = page.locator('.frames figure', { hasText: 'frame 3' });
  await frameThree.locator('button').click();
  await page.locator('.notice', { hasText: 'frame 3 requeued' }).waitFor();
  const events = page.locator('.events');
  await events.locator('td', { hasText: /^requeued frame 3: \d+ task/ }).waitFor();
  // Done again: a second SHOT_DONE, after the requeue (the newest event is on top).
  await waitFor('the shot to be done again', async () => {
    const lines = (await events.innerText()).split('\n');
    const requeued = lines.findIndex((line) => line.includes('requeued frame 3'));
    return lines.slice(0, requeued).some((line) => line.includes('SHOT_DONE'));
  }, 30000);
  log('frame 3 requeued and rendered again');

  // The priority changes.
  await page.fill('input.priority', '5');
  await page.click('button:text-is("Set")');
  await page.locator('.shot-progress .figures', { hasText: 'priority 5' }).waitFor();
  log('priority set to 5');

  // The report's plot and the task table's log are there.
  await page.locator('.report svg.plot').first().waitFor();
  await page.locator('table tbody tr td details').first().waitFor();
  await page.locator('table tbody tr td details summary').first().click();
  // Under a done attempt, what its worker logged while running it.
  const workerLog = page.locator('table tbody tr td details pre.worker-log').first();
  await workerLog.waitFor();
  const logText = await workerLog.innerText();
  if (!/task \d+: ran [0-9.]+ s; read \d+ input chunk/.test(logText) || !logText.includes('uploaded'))
    failures.push('the attempt\'s worker log is not shown: ' + logText);
  log(`a task's worker log: ${logText.split('\n').length} lines`);
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.waitForTimeout(1200);  // a poll or so, so that the screenshot shows a settled page
  await page.screenshot({ path: args.screenshot });
  log(`screenshot: ${args.screenshot}`);

  // The link `pathfarm local --http` logs carries the token in its fragment: no form.
  const linked = await (await browser.newContext()).newPage();
  await linked.goto(`${dashboard}#token=${TOKEN}`);
  await linked.locator('tr', { hasText: 'browser-shot' }).waitFor();
  if (await linked.isVisible('#token-form')) failures.push('the token in the link was not taken');
  if (new URL(linked.url()).hash.includes(TOKEN)) failures.push('the token stayed in the address bar');
  log('a link with the token opens the dashboard');

  // A link to one shot, shared with someone who types the token: the shot's page once
  // the token is given; and a link to the shot carrying the token opens it directly.
  const shared = await (await browser.newContext()).newPage();
  await shared.goto(`${dashboard}#/shot/${shotId}`);
  await shared.waitForSelector('#token-form:not([hidden])');
  await shared.fill('#token-input', TOKEN);
  await shared.click('#token-form button[type=submit]');
  await shared.locator('.shot-header h1').waitFor();
  if (!new URL(shared.url()).hash.startsWith(`#/shot/${shotId}`)) failures.push('the shared link lost its shot: ' + shared.url());
  const sharedWithToken = await (await browser.newContext()).newPage();
  await sharedWithToken.goto(`${dashboard}#/shot/${shotId}&token=${TOKEN}`);
  await sharedWithToken.locator('.shot-header h1').waitFor();
  if (new URL(sharedWithToken.url()).hash !== `#/shot/${shotId}`)
    failures.push('a shot link with the token kept the token or lost the shot: ' + sharedWithToken.url());
  log('a link to one shot opens that shot, with the token typed in or carried');
} catch (error) {
  failures.push(error.stack || String(error));
} finally {
  await browser.close();
}

if (failures.length) {
  for (const { name } of children) {
    console.log(`----- ${name}.log -----\n` + readFileSync(join(args.work, name + '.log'), 'utf8').slice(-3000));
  }
  console.log('FAILED:\n' + failures.join('\n'));
  process.exit(1);
}
log('dashboard browser test passed');
process.exit(0);
