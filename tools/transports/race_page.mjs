// One player races from the game page in headless Chromium (the chart of
// tools/transports/transport_chart.py, and the browser tests under loss):
// opens BASE_URL?name=NAME (&transport=websocket for "websocket"), checks
// that the page races over that transport, drives with the keys a player
// would press (the follow-the-gates helper of the drive tests) until its
// car finishes, stays until the server closes after the race, and prints
// one JSON line: the page's network figures (the
// client's `net`), its transport, and whether it finished.
// Usage: node race_page.mjs BASE_URL TRANSPORT NAME (TRANSPORT: webrtc | websocket)
import { launchChromium } from '../../tests/browser/page_checks.mjs';
import { hold, keysFor } from '../../tests/browser/drive_keys.mjs';

const [base, transport, name] = process.argv.slice(2);
if (!base || !['webrtc', 'websocket'].includes(transport) || !name) {
  console.error('usage: node race_page.mjs BASE_URL webrtc|websocket NAME');
  process.exit(2);
}
const guard = 180000;  // a bound on waiting for the race, not a timed assertion

const state = (page) => page.evaluate(() => window.jetrace.state());
const browser = await launchChromium();
let code = 0;
try {
  const page = await browser.newPage();
  // A small view: the software renderer drawing 1280x720 at 60 frames a
  // second would take the CPU the server and the clients need on 2 cores.
  await page.setViewport({ width: 320, height: 180 });
  page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
  const query = `?name=${encodeURIComponent(name)}` + (transport === 'websocket' ? '&transport=websocket' : '');
  await page.goto(base + query, { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().ownSlot >= 0, { timeout: guard });
  let s = await state(page);
  if (s.transport !== transport) throw new Error(`the page races over ${s.transport}, not ${transport} (${s.transportWhy || ''})`);
  const gates = await page.evaluate(() => window.jetrace.gates());
  const held = new Set();
  let finished = false;
  for (const start = Date.now(); Date.now() - start < guard;) {
    s = await state(page);
    if (s.closed) break;
    finished = !!s.standings.find((r) => r.slot === s.ownSlot)?.finished;
    if (finished) break;
    const car = s.cars.find((c) => c.slot === s.ownSlot);
    if (car && s.phase === 'racing') await hold(page, held, keysFor(car, gates));
    else await new Promise((r) => setTimeout(r, 20));
  }
  await hold(page, held, new Set());
  // The page's standings come from its own view of the race: it stays
  // connected until the server ends the race and closes (the server's
  // results must list it as finished too).
  for (const start = Date.now(); finished && !s.closed && Date.now() - start < guard;) {
    await new Promise((r) => setTimeout(r, 100));
    s = await state(page);
  }
  s = await state(page);
  console.log(JSON.stringify({ name, transport: s.transport, finished, net: s.net }));
  if (!finished) code = 1;
} finally {
  await browser.close();
}
process.exit(code);
