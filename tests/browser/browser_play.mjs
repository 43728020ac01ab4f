// Races from the page jetrace-server --web serves, in headless Chromium
// (see browser_play.sh): the client library in WebAssembly joins over the
// server's WebSocket, and the test drives it with the keys a player would
// press (the follow-the-gates helper), until the car finishes. A second
// page watches (?watch), a third comes when the race is full and must show
// the refusal's reason.
// The ticks whose drawn position the page compared with the server's go to
// SAMPLES.json, for browser_play.sh to check against the recording.
// TRANSPORT: the page's transport the test expects ("websocket": the page
// is told ?transport=websocket; "webrtc": it prefers the data channel;
// "fallback": the data channel cannot connect and the page falls back to
// the WebSocket).
// Usage: node browser_play.mjs BASE_URL SHOT.png METRICS_URL SAMPLES.json [TRANSPORT]
import { writeFileSync } from 'node:fs';
import { check, distinctColours, launchChromium } from './page_checks.mjs';
import { hold, keysFor } from './drive_keys.mjs';

const [base, shotPath, metricsUrl, samplesPath, mode = 'websocket'] = process.argv.slice(2);
const expected = mode === 'webrtc' ? 'webrtc' : 'websocket';
const transportQuery = mode === 'websocket' ? '&transport=websocket' : '';
const hudName = { webrtc: 'WebRTC', websocket: 'WebSocket' }[expected];
const guard = { timeout: 90000 };  // a bound on waiting, not a timed assertion

const state = (page) => page.evaluate(() => window.jetrace.state());
const own = (s) => s.cars.find((c) => c.slot === s.ownSlot);

async function open(browser, query) {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log(`page ${query} error: ${e.message}`));
  await page.goto(base + query + transportQuery, { waitUntil: 'load' });
  return page;
}

const browser = await launchChromium();
try {
  const opened = Date.now();
  const driver = await open(browser, '?name=human');
  await driver.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().frames > 0, guard);
  let s = await state(driver);
  console.log(`page ready (track drawn, first frame) ${Date.now() - opened} ms after opening the URL`);
  check(s.source === 'client', 'the page runs the WebAssembly client');
  check(s.transport === expected, `the page races over ${expected} (${s.transport}${s.transportWhy ? ': ' + s.transportWhy : ''})`);
  if (expected === 'webrtc') check(s.rtcMode === 'worker', `the data channels moved to the worker (${s.rtcMode})`);
  check(s.mode === 'drive' && s.ownSlot >= 0, `drive mode, the own car's slot ${s.ownSlot}`);
  const gates = await driver.evaluate(() => window.jetrace.gates());
  check(gates.length > 1, `the page has the track's gates (${gates.length})`);

  const watcher = await open(browser, '?watch');
  await watcher.waitForFunction(() => window.jetrace && window.jetrace.state().frames > 0, guard);
  // The race is full (3 players): a late page is refused and says why.
  const late = await open(browser, '?name=late');
  await late.waitForFunction(() => window.jetrace && window.jetrace.state().closed, guard);
  const l = await state(late);
  check(/code 2003/.test(l.closeText) && /full/.test(l.closeText), `a late page shows its refusal: "${l.closeText}"`);

  for (let t0 = Date.now(); s.phase !== 'racing' && Date.now() - t0 < guard.timeout;) {
    await new Promise((r) => setTimeout(r, 50));
    s = await state(driver);
  }
  check(s.phase === 'racing', 'the race started');
  check(s.cars.length === 3, `the driver's page shows 3 cars (${s.cars.length})`);
  check(s.standings.some((r) => r.name === 'robot0') && s.standings.some((r) => r.name === 'robot1'),
    'the standings name both bots');
  const metrics = await (await fetch(metricsUrl)).text();
  const gauge = (t) => Number((metrics.match(new RegExp(`jetrace_transport_players\\{transport="${t}"\\} (\\S+)`)) || [])[1]);
  check(gauge(expected) === 1 && gauge('enet') === 2,
    `the metrics count 1 player over ${expected} and 2 over ENet (${gauge(expected)}, ${gauge('enet')})`);
  const status = await (await fetch(metricsUrl.replace(/\/metrics$/, '/status'))).json();
  const human = status.players.find((p) => p.name === 'human');
  check(human && human.transport === expected, `/status names the page's transport (${human && human.transport})`);
  const hud = await driver.evaluate(() => document.getElementById('hud-net').textContent);
  check(hud.startsWith(hudName + ' ·'), `the HUD shows the transport: "${hud}"`);

  const held = new Set();
  let top = 0, steps = 0;
  // Where the page drew its car at ticks the server confirmed, with its
  // own verdict (same, or the cause).
  const samples = [];
  const start = Date.now();
  while (Date.now() - start < 120000) {
    s = await state(driver);
    const d = s.net && s.net.drawn;
    if (d && (samples.length === 0 || samples[samples.length - 1].tick !== d.tick)) samples.push({ ...d, slot: s.ownSlot });
    const car = own(s);
    if (!car) continue;
    top = Math.max(top, car.speed);
    if (s.standings.find((r) => r.slot === s.ownSlot)?.finished) break;
    await hold(driver, held, keysFor(car, gates));
    if (++steps % 40 === 0) console.log(`tick ${s.tick} lap ${car.lap} gate ${car.gate} speed ${car.speed} rtt ${s.net.rtt_ms} ms`);
  }
  await hold(driver, held, new Set());
  s = await state(driver);
  const mine = s.standings.find((r) => r.slot === s.ownSlot);
  check(top > 20, `the car accelerated with the up key (top speed ${top} m/s)`);
  check(mine && mine.finished, `the page's car finished the lap (${mine ? mine.finish_s : '?'} s)`);
  console.log(JSON.stringify(s.net));
  // At 0 % loss the prediction is exact but for what it cannot know: the
  // other cars' inputs (a correction with another car near the page's), and
  // an input of its own that reached the server after its tick (the worker's
  // timers stalled by a starved CPU; the server then steps its held input).
  // Every correction must be one of those, and late inputs rare.
  const unexplained = s.net.corrections - s.net.corrections_near_car - s.net.corrections_late;
  check(unexplained === 0 && s.net.late_inputs * 20 < s.net.snapshots,
    `no corrections on loopback but touches and late inputs (${s.net.corrections} in ${s.net.snapshots} snapshots: ` +
    `${s.net.corrections_near_car} near another car, ${s.net.corrections_late} late; ${s.net.late_inputs} inputs late)`);
  check(s.net.rtt_ms > 0 && s.net.rtt_ms < 200, `a round trip is shown (${s.net.rtt_ms} ms)`);
  // Where the page drew its car, against the server's position at each
  // confirmed tick: off only near another car or after a late input.
  check(s.net.drawn_checked * 2 > s.net.snapshots && s.net.drawn_off_unexplained === 0,
    `the page drew its car where the server had it but for touches and late inputs (${s.net.drawn_off} ` +
    `of ${s.net.drawn_checked} ticks off, ${s.net.drawn_off_unexplained} of them unexplained)`);
  writeFileSync(samplesPath, JSON.stringify(samples));
  const seconds = (Date.now() - opened) / 1000;
  console.log(JSON.stringify({ figure: 'browser_player_traffic', cars: 3, seconds: Math.round(seconds),
    ...s.traffic, kbit_s_down: Math.round(s.traffic.bytes_down * 8 / seconds / 100) / 10,
    kbit_s_up: Math.round(s.traffic.bytes_up * 8 / seconds / 100) / 10 }));

  const w = await state(watcher);
  check(w.mode === 'live' && w.ownSlot === -1, `the ?watch page watches (mode ${w.mode}, own slot ${w.ownSlot})`);
  check(w.cars.length === 3, `the ?watch page shows every car (${w.cars.length})`);
  const png = await driver.screenshot({ path: shotPath });
  const colours = await distinctColours(driver, png);
  check(colours > 50, `the 3D view is not blank (${colours} distinct colours)`);

} finally {
  await browser.close();
}
