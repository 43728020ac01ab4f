// The client library in WebAssembly (jetrace_web.js, client/web/), run in
// a Web Worker so that drawing the page never holds back its ticks: it
// joins jetrace-server's race over a WebSocket to /play, predicts the own
// car with the shared core and reconciles it with the server's snapshots,
// exactly as jetrace-bot does. This file is its transport shim (one binary
// frame: a channel byte and one protocol message) and its clock; the page
// (client_source.js) sends it the input and gets the hello and frames.
import createJetrace from '/jetrace_web.js';
import { closeText } from './close_text.js';

const sockets = new Map();
// 'webrtc': the socket rides the page's data channels (rtc_link.js):
// `channels` when the page moved them here, else the page relays frames.
// rtcId: the id of the socket riding them, while they are open.
let transport = 'websocket', rtcId = null, rtcOpen = false, channels = null;
const traffic = { bytes_down: 0, bytes_up: 0, frames_down: 0, frames_up: 0 };
let M = null;
let input = { keys: { up: false, left: false, right: false, brake: false }, pad: null };
let hello = false, closed = false, lastTick = -2, lastFrameAt = 0;

function received(id, buffer) {
  const bytes = new Uint8Array(buffer);
  traffic.bytes_down += bytes.length;
  traffic.frames_down++;
  const p = M._malloc(bytes.length);
  M.HEAPU8.set(bytes, p);
  M._jr_socket_frame(id, p, bytes.length);
  M._free(p);
}

const hooks = {
  open(id) {
    if (transport === 'webrtc' && rtcOpen && rtcId === null) {
      rtcId = id;
      setTimeout(() => { M._jr_socket_opened(id); step(); }, 0);
      return;
    }
    const scheme = self.location.protocol === 'https:' ? 'wss://' : 'ws://';
    const ws = new WebSocket(scheme + self.location.host + '/play');
    ws.binaryType = 'arraybuffer';
    sockets.set(id, ws);
    ws.onopen = () => { M._jr_socket_opened(id); step(); };
    ws.onmessage = (e) => {
      if (e.data instanceof ArrayBuffer) received(id, e.data);
    };
    ws.onclose = (e) => { sockets.delete(id); M._jr_socket_closed(id, e.code); step(); };
  },
  send(id, channel, bytes) {
    if (id === rtcId) {
      if (!rtcOpen) return false;
      if (channels) {
        const c = channels[channel];
        if (!c || c.readyState !== 'open') return false;
        c.send(bytes.slice());  // a copy: `bytes` views the WebAssembly heap
      } else {
        const frame = new Uint8Array(bytes.length + 1);
        frame[0] = channel;
        frame.set(bytes, 1);
        postMessage({ type: 'rtc-send', frame: frame.buffer }, [frame.buffer]);
      }
      traffic.bytes_up += bytes.length + 1;
      traffic.frames_up++;
      return true;
    }
    const ws = sockets.get(id);
    if (!ws || ws.readyState !== WebSocket.OPEN) return false;
    const frame = new Uint8Array(bytes.length + 1);
    frame[0] = channel;
    frame.set(bytes, 1);
    ws.send(frame);
    traffic.bytes_up += frame.length;
    traffic.frames_up++;
    return true;
  },
  close(id) {
    if (id === rtcId) {
      if (channels) channels.forEach((c) => c.close());
      postMessage({ type: 'rtc-leave' });
      return;
    }
    const ws = sockets.get(id);
    if (ws) ws.close(1000);
  },
};

// The data channels, moved here by the page: "rtc-opened" to the page when
// both are open; their messages become frames of the socket riding them.
function adoptChannels(list) {
  channels = list;
  const open = new Set();
  const opened = (channel) => {
    if (open.has(channel)) return;
    open.add(channel);
    if (open.size === channels.length) postMessage({ type: 'rtc-opened' });
  };
  channels.forEach((c, channel) => {
    c.binaryType = 'arraybuffer';
    c.onopen = () => opened(channel);
    // Already open when this worker took it (its open event not seen here).
    if (c.readyState === 'open') opened(channel);
    c.onclose = () => { postMessage({ type: 'rtc-close' }); rtcClosed(); };
    c.onmessage = (e) => {
      if (!(e.data instanceof ArrayBuffer) || rtcId === null || !rtcOpen) return;
      const frame = new Uint8Array(e.data.byteLength + 1);
      frame[0] = channel;
      frame.set(new Uint8Array(e.data), 1);
      received(rtcId, frame.buffer);
    };
  });
}

function rtcClosed() {
  if (!rtcOpen) return;
  rtcOpen = false;
  if (rtcId !== null) {
    M._jr_socket_closed(rtcId, 1006);
    step();
  }
}

function step() {
  const { keys, pad } = input;
  if (pad) M._jr_set_analog(pad.throttle, pad.steer, pad.brake ? 1 : 0);
  else M._jr_set_keys(keys.up ? 1 : 0, keys.left ? 1 : 0, keys.right ? 1 : 0, keys.brake ? 1 : 0);
  const now = performance.now();
  M._jr_update(now);
  if (!hello && M._jr_ready()) {
    hello = true;
    postMessage({ type: 'open' });
    postMessage({ type: 'message', text: M.UTF8ToString(M._jr_hello()) });
  }
  if (hello && !closed) {
    const tick = M._jr_tick();
    // A frame when the shown tick changes, and in the lobby now and then.
    if (tick !== lastTick || now - lastFrameAt > 100) {
      lastTick = tick;
      lastFrameAt = now;
      const text = M.UTF8ToString(M._jr_frame());
      if (text) postMessage({ type: 'message', text, traffic });
    }
  }
  if (!closed && M._jr_closed()) {
    closed = true;
    postMessage({ type: 'close', text: closeText(M._jr_close_code(), M.UTF8ToString(M._jr_close_reason())), traffic });
  }
}

function trackBytes() {
  const size = M._malloc(4);
  const p = M._jr_track_mesh(size);
  const n = M.HEAP32[size >> 2];
  M._free(size);
  return M.HEAPU8.slice(p, p + n).buffer;
}

async function start(options) {
  M = await createJetrace({ jetraceSocket: hooks, locateFile: (path) => '/' + path });
  const started = M.ccall('jr_start', 'number', ['string', 'number', 'string'],
    [options.name, options.watch ? 1 : 0, options.token || '']);
  if (started !== 0) {
    postMessage({ type: 'close', text: 'the connect token in the URL is not hex' });
    return;
  }
  setInterval(step, 4);
}

self.onmessage = (e) => {
  const m = e.data;
  if (m.type === 'start') {
    transport = m.transport;
    rtcOpen = transport === 'webrtc';
    start(m.options);
  } else if (m.type === 'rtc-channels') adoptChannels(m.channels);
  else if (m.type === 'rtc-drop' && channels) {
    channels.forEach((c) => c.close());
    channels = null;
  } else if (m.type === 'rtc-frame' && rtcId !== null && rtcOpen) received(rtcId, m.frame);
  else if (m.type === 'rtc-close') rtcClosed();
  else if (m.type === 'input') input = m.input;
  else if (m.type === 'track') {
    const bytes = trackBytes();
    postMessage({ type: 'track', bytes }, [bytes]);
  } else if (m.type === 'leave' && M) {
    M._jr_leave();
    step();
  }
};
