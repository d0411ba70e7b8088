// The pathfarm dashboard: reads the scheduler's /api every second and draws the farm
// (shots and workers) or one shot (progress, frames, report, tasks, events). No framework:
// the DOM is built with el(), which sets text, never HTML, so no farm string is markup.
'use strict';

const TOKEN_KEY = 'pathfarm-token';
const POLL_MS = 1000;
const TASK_PAGE = 100;

// ---- talking to the scheduler ----------------------------------------------------------

class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function api(path, options = {}) {
  const headers = { ...(options.headers || {}) };
  const token = sessionStorage.getItem(TOKEN_KEY);
  if (token) headers.Authorization = 'Bearer ' + token;
  let response;
  try {
    response = await fetch('/api' + path, { ...options, headers, cache: 'no-store' });
  } catch (e) {
    throw new ApiError(0, 'cannot reach the scheduler');
  }
  if (response.status === 401) {
    askForToken(token ? 'The token was refused; try again.' : '');
    throw new ApiError(401, 'the access token is missing or wrong');
  }
  if (!response.ok) {
    let message = response.statusText;
    try {
      message = (await response.json()).error || message;
    } catch (e) { /* not JSON: keep the status text */ }
    throw new ApiError(response.status, message);
  }
  return options.raw ? response : response.json();
}

function post(path, body = {}) {
  return api(path, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
}

// ---- small DOM and formatting helpers ---------------------------------------------------

function el(tag, attributes = {}, ...children) {
  const node = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) {
    if (value === undefined || value === null || value === false) continue;
    if (name.startsWith('on')) node.addEventListener(name.slice(2), value);
    else if (name === 'className') node.className = value;
    else node.setAttribute(name, value === true ? '' : value);
  }
  for (const child of children.flat()) {
    if (child === undefined || child === null || child === false) continue;
    node.append(child instanceof Node ? child : String(child));
  }
  return node;
}

const SVG = 'http://www.w3.org/2000/svg';
function svg(tag, attributes = {}, ...children) {
  const node = document.createElementNS(SVG, tag);
  for (const [name, value] of Object.entries(attributes)) node.setAttribute(name, value);
  for (const child of children.flat()) node.append(child instanceof Node ? child : String(child));
  return node;
}

function duration(seconds) {
  if (seconds === null || seconds === undefined || !isFinite(seconds)) return '';
  if (seconds < 10) return seconds.toFixed(1) + ' s';
  if (seconds < 60) return Math.round(seconds) + ' s';
  const s = Math.round(seconds);
  if (s < 3600) return Math.floor(s / 60) + 'm ' + String(s % 60).padStart(2, '0') + 's';
  return Math.floor(s / 3600) + 'h ' + String(Math.floor((s % 3600) / 60)).padStart(2, '0') + 'm';
}

function clock(epochSeconds) {
  return new Date(epochSeconds * 1000).toLocaleTimeString([], { hour12: false });
}

function number(value, digits = 3) {
  const n = Number(value);
  if (!isFinite(n)) return '';
  return Math.abs(n) >= 1000 ? Math.round(n).toLocaleString() : Number(n.toPrecision(digits)).toString();
}

// A figure with its 95 % interval (report.proto's Interval): "0.12 (0.10 to 0.15)"; an
// unbounded end shows as infinity.
function withInterval(interval) {
  if (!interval) return '';
  const end = (value) => (isFinite(Number(value)) ? number(value) : (Number(value) > 0 ? '\u221e' : '-\u221e'));
  return number(interval.estimate) + ' (' + end(interval.low) + ' to ' + end(interval.high) + ')';
}

function badge(state) {
  return el('span', { className: 'badge state-' + state }, state);
}

function progress(done, total, label) {
  const share = total > 0 ? done / total : 0;
  return el('div', { className: 'progress', title: label + ': ' + done + ' of ' + total },
    el('div', { className: 'bar', style: 'width:' + (100 * share).toFixed(1) + '%' }),
    el('span', {}, done + ' / ' + total + ' ' + label));
}

// replaceChildren() would write a null as the text "null": absent parts are dropped.
function fill(node, ...children) {
  node.replaceChildren(...children.flat().filter((child) => child !== null && child !== undefined && child !== false));
}

function section(title, ...children) {
  return el('section', { className: 'card' }, el('h2', {}, title), ...children);
}

function table(headings, rows, empty) {
  if (!rows.length) return el('p', { className: 'empty' }, empty);
  return el('table', {}, el('thead', {}, el('tr', {}, headings.map((h) => el('th', {}, h)))), el('tbody', {}, rows));
}

// ---- notices, token, liveness -----------------------------------------------------------

let noticeTimer = 0;
function notify(message, isError = false) {
  const notice = document.getElementById('notice');
  notice.textContent = message;
  notice.className = 'notice' + (isError ? ' error' : '');
  notice.hidden = false;
  clearTimeout(noticeTimer);
  noticeTimer = setTimeout(() => { notice.hidden = true; }, isError ? 8000 : 3000);
}

function askForToken(message) {
  const form = document.getElementById('token-form');
  if (!form.hidden) return;
  sessionStorage.removeItem(TOKEN_KEY);
  form.hidden = false;
  document.getElementById('view').hidden = true;
  if (message) notify(message, true);
  document.getElementById('token-input').focus();
}

function setUpToken() {
  // `pathfarm local --http` prints a link carrying the token in the fragment, which the
  // browser never sends: kept for this tab, then taken out of the address bar.
  // The rest of the fragment is the page it links to (a shot's, say), which stays.
  const match = location.hash.match(/[#&]token=([^&]+)/);
  if (match) {
    sessionStorage.setItem(TOKEN_KEY, decodeURIComponent(match[1]));
    const route = location.hash.replace(/[#&]token=[^&]*/, '').replace(/^#?&?/, '#');
    history.replaceState(null, '', location.pathname + (route.length > 1 ? route : '#/'));
  }
  const form = document.getElementById('token-form');
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    sessionStorage.setItem(TOKEN_KEY, document.getElementById('token-input').value.trim());
    document.getElementById('token-input').value = '';
    form.hidden = true;
    document.getElementById('view').hidden = false;
    refresh();
  });
  const forget = document.getElementById('forget-token');
  forget.addEventListener('click', () => askForToken('Token forgotten.'));
}

function showLive(ok, message) {
  const live = document.getElementById('live');
  live.textContent = message;
  live.className = 'live ' + (ok ? 'ok' : 'down');
  document.getElementById('forget-token').hidden = !sessionStorage.getItem(TOKEN_KEY);
}

// Runs an action, says what it did, and redraws at once.
async function act(what, path, body) {
  try {
    await post(path, body);
    notify(what);
  } catch (e) {
    notify(what + ': ' + e.message, true);
  }
  refresh();
}

// ---- the farm: shots and workers --------------------------------------------------------

function shotRow(shot) {
  const open = () => { location.hash = '#/shot/' + shot.id; };
  return el('tr', { className: 'link', onclick: open },
    el('td', { className: 'num' }, shot.id),
    el('td', {}, el('a', { href: '#/shot/' + shot.id }, shot.name)),
    el('td', {}, badge(shot.state)),
    el('td', { className: 'wide' }, progress(shot.tasks_done, shot.tasks_total, 'tasks')),
    el('td', { className: 'wide' }, progress(shot.frames_done, shot.frames_total, 'frames')),
    el('td', { className: 'num' }, shot.tasks_running),
    el('td', { className: 'num' + (shot.tasks_failed ? ' bad' : '') }, shot.tasks_failed),
    el('td', { className: 'num' }, duration(shot.elapsed_seconds)),
    el('td', { className: 'num' }, shot.priority));
}

function runningTask(task) {
  return el('div', { className: 'running' },
    el('a', { href: '#/shot/' + task.shot_id }, 'shot ' + task.shot_id),
    ' \u00b7 task ' + task.task_id + ' ' + task.kind + ' frame ' + task.frame + ' \u00b7 ' +
      Math.round(100 * task.progress) + '% \u00b7 ' + duration(task.seconds));
}

function workerRows(workers) {
  return workers.map((w) => el('tr', {},
    el('td', {}, w.name, el('span', { className: 'dim' }, ' #' + w.id)),
    el('td', {}, badge(w.state)),
    el('td', { className: 'num' }, w.busy + ' / ' + w.slots),
    el('td', {}, w.tasks.length ? w.tasks.map(runningTask) : el('span', { className: 'dim' }, '\u2014')),
    el('td', { className: 'num' }, duration(w.seconds_since_seen) + ' ago'),
    el('td', { className: 'num dim' }, clock(w.last_seen))));
}

function blocklistRows(entries, withShot) {
  return entries.map((e) => el('tr', {},
    withShot ? el('td', {}, el('a', { href: '#/shot/' + e.shot_id }, 'shot ' + e.shot_id)) : null,
    el('td', {}, e.worker, el('span', { className: 'dim' }, ' #' + e.worker_id)),
    el('td', { className: 'num' }, e.failures),
    el('td', {}, el('button', {
      className: 'small',
      onclick: () => act('worker ' + e.worker_id + ' may work on shot ' + e.shot_id + ' again',
        '/shots/' + e.shot_id + '/blocklist/' + e.worker_id + '/clear'),
    }, 'Clear'))));
}

async function drawFarm(view) {
  const [{ shots }, workers] = await Promise.all([api('/shots'), api('/workers')]);
  const newestFirst = shots.slice().reverse();
  fill(view,
    section('Shots', table(
      ['#', 'name', 'state', 'tasks', 'frames', 'running', 'failed', 'elapsed', 'priority'],
      newestFirst.map(shotRow), 'No shots yet: `pathfarm submit SHOT.json` adds one.')),
    section('Workers', table(['worker', 'state', 'busy / slots', 'current tasks', 'last heard', 'at'],
      workerRows(workers.workers), 'No worker has registered yet.')),
    section('Blocklist', table(['shot', 'worker', 'failures', ''], blocklistRows(workers.blocklist, true),
      'No worker is blocklisted.')));
}

// ---- one shot ---------------------------------------------------------------------------

// What the shot page keeps between polls: the parts the user is working with.
const shotPage = {
  id: 0,
  root: null,
  parts: {},
  taskFilter: '',
  taskOffset: 0,
  openTasks: new Set(),
  thumbnails: new Map(),  // chunk sha256 -> object URL
  framesKey: null,        // the frames drawn, by their chunks
  reportKey: '',
  reportAt: 0,
};

function buildShotPage(id) {
  const p = shotPage;
  p.id = id;
  p.taskFilter = '';
  p.taskOffset = 0;
  p.openTasks.clear();
  p.reportKey = '';
  p.framesKey = null;
  const parts = {
    header: el('div', { className: 'shot-header' }),
    progress: el('div', { className: 'shot-progress' }),
    spec: el('p', { className: 'dim spec' }),
    frames: el('div', { className: 'frames' }),
    report: el('div', { className: 'report' }),
    tasks: el('div'),
    pager: el('div', { className: 'pager' }),
    blocklist: el('div'),
    events: el('div', { className: 'events' }),
  };
  const priority = el('input', { type: 'number', step: '1', className: 'priority', 'aria-label': 'priority' });
  const filter = el('select', { 'aria-label': 'task state' },
    ['', 'waiting', 'ready', 'leased', 'done', 'failed'].map((s) => el('option', { value: s }, s || 'every state')));
  filter.addEventListener('change', () => {
    p.taskFilter = filter.value;
    p.taskOffset = 0;
    refresh();
  });
  const control = (label, verb, className) => el('button', {
    className, onclick: () => act(label + ' shot ' + id, '/shots/' + id + '/' + verb),
  }, label);
  parts.priority = priority;
  p.parts = parts;
  p.root = el('div', {},
    el('p', {}, el('a', { href: '#/' }, '\u2190 all shots')),
    el('section', { className: 'card' }, parts.header,
      el('div', { className: 'actions' },
        control('Pause', 'pause'), control('Resume', 'resume'), control('Retry', 'retry'),
        control('Cancel', 'cancel', 'danger'),
        el('span', { className: 'gap' }),
        el('label', {}, 'priority ', priority),
        el('button', {
          onclick: () => act('priority of shot ' + id + ' set to ' + priority.value, '/shots/' + id + '/priority',
            { priority: Number(priority.value) }),
        }, 'Set')),
      parts.progress, parts.spec),
    section('Frames', parts.frames),
    section('Speed against error', parts.report),
    section('Tasks', el('div', { className: 'toolbar' }, filter, parts.pager), parts.tasks),
    section('Blocklist', parts.blocklist),
    section('Events', parts.events));
  return p.root;
}

function drawShotSummary(page) {
  const p = shotPage;
  const s = page.summary;
  fill(p.parts.header,
    el('h1', {}, s.name, el('span', { className: 'dim' }, ' #' + s.id), ' ', badge(s.state)),
    s.failure ? el('p', { className: 'bad' }, s.failure) : null);
  if (document.activeElement !== p.parts.priority) p.parts.priority.value = s.priority;
  fill(p.parts.progress,
    progress(s.tasks_done, s.tasks_total, 'tasks'),
    progress(s.frames_done, s.frames_total, 'frames'),
    el('div', { className: 'figures' },
      el('span', {}, 'elapsed ', el('b', {}, duration(s.elapsed_seconds))),
      el('span', {}, 'running ', el('b', {}, s.tasks_running)),
      el('span', {}, 'failed ', el('b', { className: s.tasks_failed ? 'bad' : '' }, s.tasks_failed)),
      el('span', {}, 'attempts ', el('b', {}, s.attempts)),
      el('span', {}, 'workers busy ', el('b', {}, s.workers_busy)),
      el('span', {}, 'priority ', el('b', {}, s.priority))));
  const spec = page.spec;
  p.parts.spec.textContent = spec.pipeline + ' \u00b7 frames ' + spec.frame_start + '\u2013' + spec.frame_end +
    ' \u00b7 ' + spec.width + '\u00d7' + spec.height + ' \u00b7 ' + spec.spp + ' spp \u00b7 ' + spec.tile +
    ' px tiles \u00b7 ' + spec.scene;
  fill(p.parts.blocklist, table(['worker', 'failures', ''],
    blocklistRows(page.blocklist, false), 'No worker is blocklisted for this shot.'));
  fill(p.parts.events, table(['time', 'event'],
    page.events.slice().reverse().map((e) => el('tr', {},
      el('td', { className: 'num dim' }, clock(e.time)), el('td', {}, e.message))),
    'No events.'));
}

async function thumbnailUrl(shotId, frame) {
  const cached = shotPage.thumbnails.get(frame.sha256);
  if (cached) return cached;
  const response = await api('/shots/' + shotId + '/frames/' + frame.frame + '/thumbnail.png', { raw: true });
  const url = URL.createObjectURL(await response.blob());
  shotPage.thumbnails.set(frame.sha256, url);
  return url;
}

async function drawFrames(page) {
  const p = shotPage;
  const id = page.summary.id;
  const framesKey = page.frames.map((f) => f.sha256).join();
  if (framesKey === p.framesKey) return;
  const figures = [];
  for (const frame of page.frames) {
    let picture;
    try {
      picture = el('img', { src: await thumbnailUrl(id, frame), alt: 'frame ' + frame.frame });
    } catch (e) {
      picture = el('div', { className: 'missing' }, e.message);
    }
    figures.push(el('figure', {}, picture,
      el('figcaption', {}, 'frame ' + frame.frame, el('button', {
        className: 'small', title: 'render this frame again',
        onclick: () => act('frame ' + frame.frame + ' requeued', '/shots/' + id + '/frames/' + frame.frame + '/requeue'),
      }, 'Requeue'))));
  }
  if (p.id !== id) return;  // the user moved on while the pictures loaded
  p.framesKey = framesKey;
  fill(p.parts.frames, figures.length ? figures : el('p', { className: 'empty' }, 'No frame is done yet.'));
}

function taskRow(task, shotId) {
  const p = shotPage;
  const where = task.window ? ' [' + task.window[0] + ',' + task.window[2] + ')\u00d7[' + task.window[1] + ',' +
    task.window[3] + ')' : '';
  // The open state is kept at the click itself: the toggle event comes later, and a poll
  // that redraws the table in between would draw this task closed again.
  const remember = () => {
    if (details.open) p.openTasks.delete(task.id);
    else p.openTasks.add(task.id);
  };
  const details = el('details', { open: p.openTasks.has(task.id) },
    el('summary', { onclick: remember }, task.attempts.length + ' attempt' + (task.attempts.length === 1 ? '' : 's') +
      (task.log.length ? ', ' + task.log.length + ' event' + (task.log.length === 1 ? '' : 's') : '')),
    el('ul', { className: 'log' },
      task.attempts.map((a) => el('li', {},
        el('span', { className: 'dim' }, clock(a.leased_at) + ' '),
        'attempt ' + a.id + ' on ' + (a.worker || 'worker ' + a.worker_id) + ': ', badge(a.state),
        ' ' + duration(a.seconds) + (a.state === 'running' ? ', ' + Math.round(100 * a.progress) + '%' : ''),
        a.error ? el('span', { className: 'bad' }, ' \u2014 ' + (a.failure_class ? a.failure_class.replace('_', ' ') + ': ' : '') + a.error) : null,
        a.log_tail ? el('pre', { className: 'worker-log' }, a.log_tail) : null)),
      task.log.map((e) => el('li', {}, el('span', { className: 'dim' }, clock(e.time) + ' '), e.message))));
  details.addEventListener('toggle', () => {
    if (details.open) p.openTasks.add(task.id);
    else p.openTasks.delete(task.id);
  });
  return el('tr', {},
    el('td', { className: 'num' }, task.id),
    el('td', {}, task.kind, el('span', { className: 'dim' }, where)),
    el('td', { className: 'num' }, task.frame),
    el('td', {}, badge(task.state)),
    el('td', {}, task.worker),
    el('td', { className: 'num' }, task.attempts.length + ' / ' + task.max_attempts),
    el('td', { className: 'num' }, duration(task.seconds)),
    el('td', { className: 'log-cell' }, details),
    el('td', {}, el('button', {
      className: 'small', title: 'run this task (and what uses it) again',
      onclick: () => act('task ' + task.id + ' requeued', '/shots/' + shotId + '/tasks/' + task.id + '/requeue'),
    }, 'Requeue')));
}

async function drawTasks(id) {
  const p = shotPage;
  const query = '?offset=' + p.taskOffset + '&limit=' + TASK_PAGE + (p.taskFilter ? '&state=' + p.taskFilter : '');
  const page = await api('/shots/' + id + '/tasks' + query);
  if (p.id !== id) return;
  fill(p.parts.tasks, table(
    ['#', 'kind', 'frame', 'state', 'worker', 'attempts', 'duration', 'log', ''],
    page.tasks.map((t) => taskRow(t, id)), 'No task in this state.'));
  const last = Math.min(page.matching, p.taskOffset + TASK_PAGE);
  const move = (offset) => () => { p.taskOffset = offset; refresh(); };
  fill(p.parts.pager,
    el('button', { className: 'small', disabled: p.taskOffset === 0, onclick: move(Math.max(0, p.taskOffset - TASK_PAGE)) },
      '\u2190'),
    el('span', {}, (page.matching ? p.taskOffset + 1 : 0) + '\u2013' + last + ' of ' + page.matching),
    el('button', { className: 'small', disabled: last >= page.matching, onclick: move(p.taskOffset + TASK_PAGE) },
      '\u2192'));
}

// ---- the report: speed against error ----------------------------------------------------

function stageBars(stages) {
  const width = 420, row = 22, label = 90, value = 110;
  const largest = Math.max(...stages.map((s) => s.core_seconds_per_frame), 1e-9);
  return svg('svg', { viewBox: '0 0 ' + width + ' ' + (row * stages.length + 4), class: 'plot', role: 'img' },
    svg('title', {}, 'core-seconds per frame by stage'),
    stages.map((s, i) => {
      const w = (width - label - value) * s.core_seconds_per_frame / largest;
      const y = i * row + 2;
      return svg('g', {},
        svg('text', { x: label - 6, y: y + 14, 'text-anchor': 'end' }, s.stage),
        svg('rect', { x: label, y: y + 3, width: Math.max(w, 1), height: row - 8, rx: 2, class: 'bar' }),
        svg('text', { x: label + w + 6, y: y + 14 }, number(s.core_seconds_per_frame) + ' core-s'));
    }));
}

// Cost per frame against relMSE, both axes logarithmic. Plain pt's error falls as 1/spp,
// so every pt render lies on the line through its point with slope -1: a pipeline below
// that line paid less than pt for the same error.
function speedErrorPlot(report) {
  const final = (report.errors || []).find((e) => e.stage === 'final');
  const baseline = (report.errors || []).find((e) => e.stage === 'baseline');
  const ptCost = report.baseline_core_seconds_per_frame;
  if (!final || !baseline || !(ptCost > 0) || !(final.relmse > 0) || !(baseline.relmse > 0)) return null;
  const points = [
    { name: report.pipeline, cost: report.core_seconds_per_frame, error: final.relmse, className: 'ours' },
    { name: 'pt, same spp', cost: ptCost, error: baseline.relmse, className: 'pt' },
  ];
  const costs = points.map((q) => Math.log10(q.cost)), errors = points.map((q) => Math.log10(q.error));
  const lo = (v) => Math.floor(Math.min(...v) - 0.5), hi = (v) => Math.ceil(Math.max(...v) + 0.5);
  const [x0, x1, y0, y1] = [lo(costs), hi(costs), lo(errors), hi(errors)];
  const W = 420, H = 240, m = { l: 56, r: 12, t: 10, b: 36 };
  const X = (c) => m.l + (W - m.l - m.r) * (Math.log10(c) - x0) / (x1 - x0);
  const Y = (e) => H - m.b - (H - m.t - m.b) * (Math.log10(e) - y0) / (y1 - y0);
  const ticks = [];
  for (let d = x0; d <= x1; ++d) ticks.push(svg('text', { x: X(10 ** d), y: H - m.b + 16, 'text-anchor': 'middle' }, '1e' + d));
  for (let d = y0; d <= y1; ++d) ticks.push(svg('text', { x: m.l - 6, y: Y(10 ** d) + 4, 'text-anchor': 'end' }, '1e' + d));
  // pt's line: error x cost = constant, clipped to the plot.
  const k = baseline.relmse * ptCost;
  const lineFrom = Math.max(10 ** x0, k / 10 ** y1), lineTo = Math.min(10 ** x1, k / 10 ** y0);
  return svg('svg', { viewBox: '0 0 ' + W + ' ' + H, class: 'plot', role: 'img' },
    svg('title', {}, 'relMSE against core-seconds per frame'),
    svg('rect', { x: m.l, y: m.t, width: W - m.l - m.r, height: H - m.t - m.b, class: 'frame' }),
    ticks,
    svg('line', { x1: X(lineFrom), y1: Y(k / lineFrom), x2: X(lineTo), y2: Y(k / lineTo), class: 'pt-line' }),
    points.map((q) => svg('g', {},
      svg('circle', { cx: X(q.cost), cy: Y(q.error), r: 5, class: q.className }),
      svg('text', { x: X(q.cost) + 8, y: Y(q.error) - 6 }, q.name))),
    svg('text', { x: (W + m.l) / 2, y: H - 4, 'text-anchor': 'middle' }, 'core-seconds per frame'),
    svg('text', { x: 12, y: (H - m.b) / 2, transform: 'rotate(-90 12 ' + (H - m.b) / 2 + ')', 'text-anchor': 'middle' },
      'relMSE'));
}

function drawReport(report) {
  const figure = (label, value) => el('span', {}, label + ' ', el('b', {}, value));
  const errors = report.errors || [];
  fill(shotPage.parts.report,
    el('div', { className: 'figures' },
      figure('core-seconds', number(report.core_seconds)),
      figure('per frame', number(report.core_seconds_per_frame)),
      report.baseline_core_seconds_per_frame > 0 ? figure('relative cost', number(report.relative_cost)) : null,
      figure('resolution gain', number(report.resolution_gain)),
      figure('re-rendered', number(100 * report.rerender_rate) + '%'),
      report.cost_at_equal_error >= 0 ?
        figure('cost at equal error (95 %)', withInterval(report.cost_at_equal_error_interval)) : null),
    report.verdict ? el('p', {}, report.verdict) : null,
    el('div', { className: 'plots' },
      (report.stages || []).length ? stageBars(report.stages) : el('p', { className: 'empty' }, 'No stage is done yet.'),
      speedErrorPlot(report)),
    errors.length ? table(['stage', 'relMSE', 'against the truth (95 %)', 'worst tile', 'worst tile, truth (95 %)',
      'worst 1 % share', 'kept'],
      errors.map((e) => el('tr', {}, el('td', {}, e.stage), el('td', { className: 'num' }, number(e.relmse)),
        el('td', { className: 'num' }, withInterval(e.truth_error)),
        el('td', { className: 'num' }, number(e.worst_tile_relmse)),
        el('td', { className: 'num' }, withInterval(e.worst_tile_truth_error)),
        el('td', { className: 'num' }, number(100 * e.worst_percent_share) + '%'),
        el('td', { className: 'num' }, number(100 * e.kept) + '%'))), '') :
      el('p', { className: 'dim' }, 'No error figures: the shot has no reference (reference_spp).'));
}

async function drawShot(view, id) {
  const p = shotPage;
  if (p.id !== id || !view.contains(p.root)) fill(view, buildShotPage(id));
  const page = await api('/shots/' + id);
  if (p.id !== id) return;
  drawShotSummary(page);
  // The report reads every task: asked for again when the shot moved, at most every 5 s.
  const reportKey = page.summary.tasks_done + '/' + page.summary.tasks_total + '/' + page.summary.state;
  const now = Date.now();
  const work = [drawTasks(id), drawFrames(page)];
  if (reportKey !== p.reportKey && (now - p.reportAt > 5000 || !p.reportKey || page.summary.state === 'done')) {
    p.reportKey = reportKey;
    p.reportAt = now;
    work.push(api('/shots/' + id + '/report').then((report) => { if (p.id === id) drawReport(report); }));
  }
  await Promise.all(work);
}

// ---- routing and polling ----------------------------------------------------------------

let busy = false;
async function refresh() {
  if (busy || !document.getElementById('token-form').hidden) return;
  busy = true;
  const view = document.getElementById('view');
  try {
    const shot = location.hash.match(/^#\/shot\/(\d+)/);
    if (shot) await drawShot(view, Number(shot[1]));
    else {
      shotPage.id = 0;
      await drawFarm(view);
    }
    showLive(true, 'live \u00b7 ' + new Date().toLocaleTimeString([], { hour12: false }));
  } catch (e) {
    if (e.status !== 401) showLive(false, e.message);
    if (e.status === 404 && location.hash.startsWith('#/shot/')) fill(view,
      section('Not found', el('p', {}, e.message), el('a', { href: '#/' }, 'all shots')));
  } finally {
    busy = false;
  }
}

setUpToken();
window.addEventListener('hashchange', refresh);
refresh();
setInterval(refresh, POLL_MS);
