// The page's side of the WebAssembly client (client_worker.js runs it in a
// Web Worker): hands it the keys the page sends and a gamepad's input (the
// Gamepad API lives on the page), and passes on its hello, frames and close.
// A gamepad in use wins over the keys: the right trigger (or A)
// accelerates, the left stick steers, the left trigger (or B) brakes.
function gamepadInput() {
  const pads = navigator.getGamepads ? [...navigator.getGamepads()] : [];
  for (const p of pads) {
    if (!p || !p.connected) continue;
    const steer = Math.abs(p.axes[0] || 0) > 0.15 ? p.axes[0] : 0;
    const rt = p.buttons[7] ? p.buttons[7].value : 0, lt = p.buttons[6] ? p.buttons[6].value : 0;
    const throttle = Math.max(rt, p.buttons[0] && p.buttons[0].pressed ? 1 : 0);
    const brake = lt > 0.5 || Boolean(p.buttons[1] && p.buttons[1].pressed);
    if (steer !== 0 || throttle > 0.05 || brake) return { throttle, steer, brake };
  }
  return null;
}

import { openRtcLink } from './rtc_link.js';

/// How long the data channels may take to open before the page races over
/// the WebSocket instead (unit: ms).
const kRtcOpenMs = 3000;

// Which transport the worker's socket uses: the WebRTC data channels when
// they open in time, else the WebSocket (docs/BROWSER.md). ?transport=websocket
// goes straight to the WebSocket.
async function chooseTransport(options, worker) {
  if (options.transport === 'websocket') return { name: 'websocket', why: 'asked for (?transport=websocket)' };
  try {
    return { name: 'webrtc', link: await openRtcLink(kRtcOpenMs, worker) };
  } catch (e) {
    console.log('jetrace: no WebRTC data channel (' + e.message + '): racing over the WebSocket');
    return { name: 'websocket', why: e.message };
  }
}

// options: {name, watch, token (hex), transport ('websocket' or null)}.
export function clientSource(options) {
  const handlers = { open() {}, close() {}, message() {} };
  const worker = new Worker('/client_worker.js', { type: 'module' });
  let traffic = { bytes_down: 0, bytes_up: 0, frames_down: 0, frames_up: 0 };
  let trackWaiter = null;
  let transport = null;
  const input = { keys: { up: false, left: false, right: false, brake: false }, pad: null };
  let sent = '';
  const post = () => {
    const text = JSON.stringify(input);
    if (text === sent) return;
    sent = text;
    worker.postMessage({ type: 'input', input });
  };
  worker.onmessage = (e) => {
    const m = e.data;
    if (m.traffic) traffic = m.traffic;
    if (m.type === 'open') handlers.open();
    else if (m.type === 'message') handlers.message(m.text);
    else if (m.type === 'close') handlers.close(m.text);
    else if (m.type === 'track' && trackWaiter) trackWaiter(m.bytes);
    else if (m.type === 'rtc-send' && transport && transport.link) transport.link.send(m.frame);
    else if (m.type === 'rtc-leave' && transport && transport.link) transport.link.close();
  };
  worker.onerror = (e) => handlers.close('the WebAssembly client failed: ' + (e.message || 'error'));
  chooseTransport(options, worker).then((t) => {
    transport = t;
    worker.postMessage({ type: 'start', options, transport: t.name });
  });
  setInterval(() => { input.pad = gamepadInput(); post(); }, 8);
  window.addEventListener('pagehide', () => worker.postMessage({ type: 'leave' }));
  return {
    kind: 'client',
    on(h) { Object.assign(handlers, h); },
    send(msg) {
      if (msg.type !== 'keys') return;
      input.keys = { up: msg.up, left: msg.left, right: msg.right, brake: msg.brake };
      post();
    },
    sendRaw() {},
    trackBytes: () => new Promise((resolve) => { trackWaiter = resolve; worker.postMessage({ type: 'track' }); }),
    stats: () => ({ ...traffic }),
    // 'webrtc' or 'websocket' once chosen, else null.
    transport: () => (transport ? transport.name : null),
    transportWhy: () => (transport && transport.why) || null,
    // 'worker' (the channels moved to the worker) or 'relay' (this thread carries them).
    rtcMode: () => (transport && transport.link ? transport.link.mode : null),
  };
}
