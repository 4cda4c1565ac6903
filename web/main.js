// The page: tabs, the status bar, and the poll loop that refreshes the visible view.
import * as api from './api.js';
import * as servos from './servos.js';
import {$, setText} from './util.js';
import busView from './bus.js';
import tableView from './table.js';
import graphView from './graph.js';
import packetsView from './packets.js';
import faultsView from './faults.js';
import clockView from './clock.js';
import physicsView from './physics.js';

// Each view: {name, init(context), show(), hide(), poll() (awaited, the loop waits for it), periodMs,
// connected() (after every (re)connection)}; all but name optional.
const views = [busView, tableView, graphView, packetsView, faultsView, clockView, physicsView];
const byName = new Map(views.map((view) => [view.name, view]));
let current = 'bus';
let wake = null;  // resolves the poll loop's wait early (a tab change, a reconnection)

function showView(name) {
  if (!byName.has(name)) return;
  const previous = byName.get(current);
  current = name;
  for (const button of $('view-tabs').querySelectorAll('button[data-view]')) {
    button.classList.toggle('active', button.dataset.view === name);
    button.setAttribute('aria-selected', String(button.dataset.view === name));
  }
  for (const section of document.querySelectorAll('section.view')) {
    section.hidden = section.dataset.view !== name;
  }
  if (previous && previous.name !== name) previous.hide?.();
  byName.get(name).show?.();
  if (location.hash !== `#${name}`) history.replaceState(null, '', `${location.search}#${name}`);
  wake?.();
}


async function pollLoop() {
  for (;;) {
    const view = byName.get(current);
    const started = performance.now();
    if (api.isConnected() && view.poll) {
      try {
        await view.poll();
      } catch (error) {
        // A refusal is already in the status bar (the "refusal" event); anything else is a bug.
        if (error.message !== 'disconnected' && !(error instanceof api.ApiError)) console.warn(`dxlemu: ${view.name} view:`, error);
      }
    }
    const wait = Math.max(0, (view.periodMs ?? 250) - (performance.now() - started));
    await new Promise((resolve) => {
      const timer = setTimeout(resolve, wait);
      wake = () => {
        clearTimeout(timer);
        resolve();
      };
    });
    wake = null;
  }
}

function setupStatus() {
  const status = $('status');
  const lastError = $('last-error');
  const setStatus = (connected) => {
    setText(status, connected ? 'connected' : (api.hasToken() ? 'disconnected' : 'disconnected (no ?token= in the URL)'));
    status.classList.toggle('connected', connected);
    status.classList.toggle('disconnected', !connected);
    document.body.classList.toggle('offline', !connected);
  };
  setStatus(false);
  api.on('open', async () => {
    setStatus(true);
    servos.forget();
    probeReadOnly();
    try {
      await servos.refresh();
    } catch (error) {
      // The views ask again.
    }
    for (const view of views) {
      try {
        await view.connected?.();
      } catch (error) {
        if (error.message !== 'disconnected') console.warn(`dxlemu: ${view.name} view:`, error);
      }
    }
    wake?.();
  });
  api.on('close', () => setStatus(false));
  api.on('refusal', ({error, cmd}) => {
    setText(lastError, `${cmd}: ${error}`);
    lastError.title = `the last request the daemon refused (${new Date().toLocaleTimeString()})`;
    if (kReadOnly.test(error)) showReadOnly(error);
  });
  lastError.addEventListener('click', () => setText(lastError, ''));
  api.on('dropped', () => setText($('dropped-count'), api.droppedEvents()));
}

const kReadOnly = /^read-only:/;

function showReadOnly(reason) {
  $('read-only-badge').hidden = false;
  $('read-only-badge').title = reason;
  document.body.classList.add('read-only');
}

// Whether this connection may change anything: a clock.step of 0 ms changes nothing anywhere (it
// is refused as not positive, or as needing manual timing), but a read-only connection refuses
// it as read-only first.
async function probeReadOnly() {
  try {
    const reply = await api.request({cmd: 'clock.step', ms: 0}, {quiet: true});
    if (!reply.ok && kReadOnly.test(reply.error ?? '')) showReadOnly(reply.error);
  } catch (error) {
    // Disconnected: asked again on the next connection.
  }
}

// Shows or hides the Physics tab (the physics view knows whether the daemon has a world).
function setPhysicsTab(visible) {
  const button = $('view-tabs').querySelector('button[data-view="physics"]');
  button.hidden = !visible;
  if (!visible && current === 'physics') showView('bus');
}

function start() {
  setupStatus();
  const context = {showView, setPhysicsTab, currentView: () => current};
  for (const view of views) view.init?.(context);
  $('view-tabs').addEventListener('click', (event) => {
    const button = event.target.closest('button[data-view]');
    if (button) showView(button.dataset.view);
  });
  window.dxlemu = {
    api: (req) => api.request(req),
    graphCsv: () => graphView.csv(),
    graphAdd: (port, servo, item) => graphView.add(port, Number(servo), item),
    graphClear: () => graphView.clear(),
    packetsJsonl: () => packetsView.jsonl(),
    packetsPcap: () => packetsView.pcap(),
    droppedEvents: () => api.droppedEvents(),
    view: () => current,
    show: (name) => showView(name),
  };
  const initial = location.hash.slice(1);
  showView(byName.has(initial) && initial !== 'physics' ? initial : 'bus');
  if (initial === 'physics') physicsView.showWhenReady = true;
  api.connect();
  pollLoop();
}

start();
