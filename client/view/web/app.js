// jetrace's page: draws the world its source sends (docs/VIEWER.md) and
// sends the user's timeline and camera choices (replay) or the keys
// (drive). The source is jetrace-view's WebSocket, or, on the page
// jetrace-server --web serves (body data-source="client"), the client
// library in WebAssembly racing on the server itself (sources.js).
// window.jetrace is the test hook.
import * as THREE from 'three';
import { CSS2DRenderer } from 'three/addons/renderers/CSS2DRenderer.js';
import { CarObject, carColor, gateObject, trackMesh } from './scene.js';
import { Cameras } from './cameras.js';
import { Panels } from './ui.js';
import { driveKeys } from './keys.js';
import { FrameStats } from './frame_stats.js';
import { viewerSource } from './sources.js';
import { Hud } from './hud.js';

const view = document.getElementById('view');
const renderer = new THREE.WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(window.innerWidth, window.innerHeight);
view.append(renderer.domElement);
const labels = new CSS2DRenderer();
labels.setSize(window.innerWidth, window.innerHeight);
labels.domElement.style.position = 'absolute';
labels.domElement.style.top = '0';
labels.domElement.style.pointerEvents = 'none';
view.append(labels.domElement);

const scene = new THREE.Scene();
scene.background = new THREE.Color(0x1b2330);
scene.add(new THREE.HemisphereLight(0xdfe9f5, 0x2a3140, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(0.4, 1, 0.3);
scene.add(sun);
const camera = new THREE.PerspectiveCamera(55, window.innerWidth / window.innerHeight, 1, 5000);
const cameras = new Cameras(camera, renderer.domElement);
let chaseSlot = 0;

const state = { hello: null, frame: null, frames: 0, connected: false, closed: false, trackLoaded: false, waiters: [],
  firstDrawMs: null };
const cars = new Map();    // slot -> CarObject
const ghosts = [];         // per ghost replay: Map slot -> CarObject
let keys = null;           // drive mode: the keyboard
const stats = new FrameStats();  // off unless a benchmark asks (window.jetrace.measure)

const hud = new Hud();
const source = document.body.dataset.source === 'client' ? await hud.join() : viewerSource();
const send = (msg) => source.send(msg);
const panels = new Panels(send, (mode, slot) => { chaseSlot = slot; cameras.setMode(mode); redraw(); });

async function loadTrack(h) {
  scene.add(trackMesh(await source.trackBytes()));
  h.track.gates.forEach((g, i) => scene.add(gateObject(g, i)));
  cameras.fit(h.track.bounds);
  state.trackLoaded = true;
  redraw();
}

function addCar(slot, name) {
  const car = new CarObject(slot, name, state.hello.car_radius_m, false);
  cars.set(slot, car);
  scene.add(car.group);
  return car;
}

function onHello(h) {
  state.hello = h;
  panels.setHello(h);
  for (const c of h.cars) addCar(c.slot, c.name);
  h.ghosts.forEach((g) => {
    const m = new Map();
    for (const c of g.cars) {
      const car = new CarObject(c.slot, 'ghost ' + (g.index + 1) + ': ' + c.name, h.car_radius_m, true);
      m.set(c.slot, car);
      scene.add(car.group);
    }
    ghosts.push(m);
  });
  chaseSlot = h.cars.length ? h.cars[0].slot : 0;
  hud.setHello(h);
  if (h.mode === 'drive') {
    keys = driveKeys(send);
    chaseSlot = h.own_slot;
    panels.setCamera('chase', h.own_slot);
    cameras.setMode('chase');
  }
  loadTrack(h).catch((e) => panels.setConnection(String(e)));
}

// Cars not in a frame (removed from the race) are hidden.
function place(objects, list) {
  const present = new Set();
  for (const c of list) {
    const obj = objects.get(c.slot);
    if (!obj) continue;
    obj.update(c);
    present.add(c.slot);
  }
  for (const [slot, obj] of objects) if (!present.has(slot)) obj.group.visible = false;
}

// Live races: cars that join after the hello are added with the names of the standings.
function addNewCars(f) {
  for (const c of f.cars) {
    if (cars.has(c.slot)) continue;
    const s = f.standings.find((x) => x.slot === c.slot);
    addCar(c.slot, s ? s.name : 'car ' + c.slot);
    panels.addCar(c.slot, s ? s.name : 'car ' + c.slot);
  }
}

// Input to display: armed with the input a key will ask for, it counts the
// draws from the key's event to the first draw of a frame driven by it.
let inputProbe = null;
window.addEventListener('keydown', () => {
  if (inputProbe && inputProbe.t0 === null) { inputProbe.t0 = performance.now(); inputProbe.draws0 = drawCount; }
}, true);
let drawCount = 0;

function onFrame(f) {
  if (inputProbe && inputProbe.t0 !== null && inputProbe.seen === null && f.input &&
      f.input.throttle === inputProbe.want.throttle && f.input.steer === inputProbe.want.steer) {
    inputProbe.seen = { tick: f.tick };
  }
  if (state.hello.mode !== 'replay') addNewCars(f);
  place(cars, f.cars);
  f.ghosts.forEach((g) => { if (ghosts[g.index]) place(ghosts[g.index], g.cars); });
  state.frame = f;
  state.frames++;
  panels.setFrame(f, { color: (slot) => '#' + carColor(slot).getHexString() });
  hud.setFrame(f);
  state.waiters = state.waiters.filter((w) => !w(f));
  redraw();
}

source.on({
  open: () => { state.connected = true; panels.setConnection(''); },
  close: (text) => {
    state.connected = false;
    state.closed = true;
    state.closeText = text;
    panels.setConnection(text);
    hud.setClosed(text);
  },
  message: (text) => stats.message(text.length, () => {
    const msg = JSON.parse(text);
    if (msg.type === 'hello') onHello(msg);
    else if (msg.type === 'frame') onFrame(msg);
  }),
});

window.addEventListener('resize', () => {
  camera.aspect = window.innerWidth / window.innerHeight;
  camera.updateProjectionMatrix();
  renderer.setSize(window.innerWidth, window.innerHeight);
  labels.setSize(window.innerWidth, window.innerHeight);
  redraw();
});

// Draws only when something changed: a frame, the camera, the window.
let dirty = true;
const redraw = () => { dirty = true; };
cameras.controls.addEventListener('change', redraw);
renderer.setAnimationLoop(() => {
  if (!dirty) return;
  dirty = false;
  cameras.follow(cars.get(chaseSlot));
  stats.draw(() => {
    renderer.render(scene, camera);
    labels.render(scene, camera);
  });
  drawCount++;
  if (state.trackLoaded && state.firstDrawMs === null) state.firstDrawMs = performance.now();
  if (inputProbe && inputProbe.seen && !inputProbe.done) {
    inputProbe.done = true;
    inputProbe.resolve({ draws: drawCount - inputProbe.draws0, ms: performance.now() - inputProbe.t0 });
  }
});

function shown(objects) {
  return [...objects.values()].filter((o) => o.group.visible && o.seen).map((o) => ({
    slot: o.slot, name: o.name, x: o.group.position.x, y: o.group.position.y, z: o.group.position.z,
    f: [o.forward.x, o.forward.y, o.forward.z], speed: o.speed, lap: o.lap, gate: o.gate,
  }));
}

// The test hook: what the page shows, and the controls a user has.
window.jetrace = {
  state: () => ({
    connected: state.connected, closed: state.closed, trackLoaded: state.trackLoaded, frames: state.frames,
    tick: state.frame ? state.frame.tick : null, phase: state.frame ? state.frame.phase : null,
    render: state.frame && state.frame.render ? state.frame.render : null,
    playing: state.frame ? state.frame.playing : false,
    firstTick: state.hello ? state.hello.first_tick : null, lastTick: state.hello ? state.hello.last_tick : null,
    cars: shown(cars), ghosts: ghosts.map(shown),
    standings: state.frame ? state.frame.standings : [],
    mode: state.hello ? state.hello.mode : null, ownSlot: state.frame ? state.frame.own_slot : null,
    countdown: state.frame ? state.frame.countdown_s : null, keys: keys ? keys.current() : null,
    source: source.kind, transport: source.transport ? source.transport() : null,
    transportWhy: source.transportWhy ? source.transportWhy() : null,
    rtcMode: source.rtcMode ? source.rtcMode() : null, driver: state.hello ? state.hello.driver : null,
    net: state.frame && state.frame.net ? state.frame.net : null,
    closeText: state.closeText || null, traffic: source.stats(),
    // ms from navigation start to the first draw of the track with a frame.
    firstDrawMs: state.firstDrawMs,
  }),
  // The track's gates as the hello gave them (gates[0] is the start line).
  gates: () => (state.hello ? state.hello.track.gates : []),
  // Resolves with the first frame at `tick` after asking for it.
  seek: (tick) => new Promise((resolve) => {
    state.waiters.push((f) => (f.tick === tick ? (resolve(f.tick), true) : false));
    send({ type: 'seek', tick });
  }),
  play: () => send({ type: 'play' }),
  pause: () => send({ type: 'pause' }),
  speed: (value) => send({ type: 'speed', value }),
  camera: (mode) => { cameras.setMode(mode); redraw(); },
  // Benchmarks: measure(true) starts timing the draws (from now), frameTimes()
  // returns {measuring, elapsed_ms, draws, messages, message_bytes, render_ms, interval_ms, message_ms}.
  measure: (on = true) => stats.measure(on),
  frameTimes: () => stats.report(),
  // Input to display: armInput(want) before a key is pressed, then
  // inputResult() resolves with the draws and ms from the key's event to the
  // first draw of a frame whose own input is `want` ({throttle, steer}).
  armInput: (want) => {
    let resolve = null;
    const result = new Promise((r) => { resolve = r; });
    inputProbe = { want, t0: null, draws0: 0, seen: null, done: false, resolve, result };
  },
  inputResult: () => (inputProbe ? inputProbe.result : null),
  // Sends `text` as it is (tests send malformed messages with it).
  sendRaw: (text) => source.sendRaw(text),
};
