// The control API over the daemon's WebSocket (docs/control-api.md, docs/web.md): request lines
// with incrementing ids answered by Promises, event lines dispatched by their "event" key, and a
// reconnect with backoff while the daemon is away.

/** A refusal of the API: `message` is its error text, verbatim. */
export class ApiError extends Error {
  constructor(message, reply) {
    super(message);
    this.name = 'ApiError';
    this.reply = reply;
  }
}

const token = new URLSearchParams(location.search).get('token') ?? '';
const listeners = new Map();  // event name -> Set of handlers
const pending = new Map();    // request id -> {resolve, reject, quiet}
let socket = null;
let open = false;
let nextId = 1;
let backoffMs = 500;
let outbox = [];              // request lines waiting for this task to end (sent as one message)
let droppedTotal = 0;

// The server closes a socket whose message passes 64 KiB: keep each batch well under it.
const kMaxMessage = 60000;

/** Calls fn(data) for every event line with this "event", and for the page's own events:
 *  "open", "close" (connection state), "refusal" ({error, cmd}). Returns an unsubscribe. */
export function on(event, fn) {
  if (!listeners.has(event)) listeners.set(event, new Set());
  listeners.get(event).add(fn);
  return () => listeners.get(event).delete(fn);
}

function emit(event, data) {
  for (const fn of listeners.get(event) ?? []) {
    try {
      fn(data);
    } catch (error) {
      console.error(`handler of "${event}" failed:`, error);
    }
  }
}

/** Whether the WebSocket is open now. */
export function isConnected() {
  return open;
}

/** Events the server dropped for this page since it was loaded (its "dropped" lines). */
export function droppedEvents() {
  return droppedTotal;
}

/** Sends one request object (an "id" is added) and resolves with the whole reply, ok or not.
 *  Rejects only when the connection is not open or closes before the reply. A refusal is also
 *  announced as a "refusal" event unless `quiet` (probes that expect refusals). */
export function request(req, {quiet = false} = {}) {
  if (!open) return Promise.reject(new Error('disconnected'));
  const id = nextId++;
  const line = JSON.stringify({id, ...req});
  return new Promise((resolve, reject) => {
    pending.set(id, {resolve, reject, quiet, cmd: req.cmd});
    queue(line);
  });
}

/** Sends {cmd, ...args} and resolves with its result; a refusal rejects with an ApiError. */
export async function call(cmd, args = {}, options = {}) {
  const reply = await request({cmd, ...args}, options);
  if (!reply.ok) throw new ApiError(reply.error ?? 'refused', reply);
  return reply.result;
}

// Requests made in the same task go out as one message of lines (the server answers each line).
function queue(line) {
  outbox.push(line);
  if (outbox.length === 1) queueMicrotask(flush);
}

function flush() {
  let batch = [];
  let size = 0;
  const send = () => {
    if (batch.length && socket && socket.readyState === WebSocket.OPEN) socket.send(batch.join('\n'));
    batch = [];
    size = 0;
  };
  for (const line of outbox) {
    if (size + line.length + 1 > kMaxMessage) send();
    batch.push(line);
    size += line.length + 1;
  }
  send();
  outbox = [];
}

function receive(text) {
  for (const line of text.split('\n')) {
    if (!line.trim()) continue;
    let message;
    try {
      message = JSON.parse(line);
    } catch (error) {
      console.warn('dxlemu: a line that is not JSON:', line.slice(0, 200));
      continue;
    }
    if (message === null || typeof message !== 'object') continue;
    if (typeof message.event === 'string') {
      if (message.event === 'dropped') {
        droppedTotal = typeof message.total === 'number' ? message.total
                                                          : droppedTotal + (message.count ?? 0);
      }
      emit(message.event, message);
      continue;
    }
    const waiting = pending.get(message.id);
    if (!waiting) continue;
    pending.delete(message.id);
    if (!message.ok && !waiting.quiet) emit('refusal', {error: message.error ?? '', cmd: waiting.cmd});
    waiting.resolve(message);
  }
}

/** Opens the WebSocket, and opens it again (0.5 s, 1 s, 2 s ... 8 s apart) whenever it closes. */
export function connect() {
  const url = `${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws?token=${encodeURIComponent(token)}`;
  let ws;
  try {
    ws = new WebSocket(url);
  } catch (error) {
    retry();
    return;
  }
  socket = ws;
  ws.addEventListener('open', () => {
    open = true;
    backoffMs = 500;
    emit('open', {});
  });
  ws.addEventListener('message', (event) => {
    if (typeof event.data === 'string') receive(event.data);
  });
  ws.addEventListener('close', (event) => {
    const wasOpen = open;
    open = false;
    socket = null;
    for (const waiting of pending.values()) waiting.reject(new Error('disconnected'));
    pending.clear();
    outbox = [];
    emit('close', {code: event.code, reason: event.reason, wasOpen});
    retry();
  });
  // A failed connection also fires "close", which retries; "error" has nothing more to say.
  ws.addEventListener('error', () => {});
}

function retry() {
  const delay = backoffMs;
  backoffMs = Math.min(backoffMs * 2, 8000);
  setTimeout(connect, delay);
}

/** Whether the page's URL carries the token the WebSocket needs. */
export function hasToken() {
  return token !== '';
}
