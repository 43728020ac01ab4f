// Drives jetrace-view's page in headless Chromium (see viewer_replay.sh).
// Usage: node viewer_replay.mjs URL TICK EXPECTED.json EXPECTED_GHOST.json SHOT.png
import { readFileSync } from 'node:fs';
import { check, distinctColours, launchChromium } from './page_checks.mjs';

const [url, tickText, expectedPath, ghostPath, shotPath] = process.argv.slice(2);
const tick = Number(tickText);
const expected = JSON.parse(readFileSync(expectedPath, 'utf8'));
const expectedGhost = JSON.parse(readFileSync(ghostPath, 'utf8'));
const guard = { timeout: 90000 };  // a bound on waiting, not a timed assertion

// The page's cars must be exactly (===) the re-simulated ones.
function samePositions(shown, want, what) {
  check(shown.length === want.cars.length, `${what}: ${want.cars.length} cars shown (got ${shown.length})`);
  for (const w of want.cars) {
    const s = shown.find((c) => c.slot === w.slot);
    check(s && s.x === w.p[0] && s.y === w.p[1] && s.z === w.p[2],
      `${what}: car ${w.slot} at exactly ${w.p.join(', ')} (shown ${s ? [s.x, s.y, s.z].join(', ') : 'nothing'})`);
  }
}

async function openPage(browser) {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log('page error: ' + e.message));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().frames > 0, guard);
  return page;
}

// Opens a second WebSocket inside `page`, sends `payload` and resolves with the close code.
function malformed(page, payload, binary) {
  return page.evaluate((text, asBinary) => new Promise((resolve) => {
    const ws = new WebSocket('ws://' + location.host + '/ws');
    ws.onopen = () => ws.send(asBinary ? new Uint8Array([1, 2, 3]) : text);
    ws.onclose = (e) => resolve(e.code);
  }), payload, binary);
}

const browser = await launchChromium();
try {
  const page = await openPage(browser);
  const first = await page.evaluate(() => window.jetrace.state());
  check(first.tick === first.firstTick && !first.playing, 'starts paused at the first tick (--paused)');
  check(first.ghosts.length === 1 && first.ghosts[0].length === 2, 'the ghost replay adds its 2 cars');

  await page.evaluate((t) => window.jetrace.seek(t), tick);
  let s = await page.evaluate(() => window.jetrace.state());
  check(s.tick === tick, `shows tick ${tick} after seeking`);
  samePositions(s.cars, expected, 'seek forward');
  samePositions(s.ghosts[0], expectedGhost, 'ghost after seek forward');
  check(s.standings.length === 3 && s.standings[0].pos === 1, 'standings of the 3 cars');

  // Back from the end: re-simulated from a kept state, it must agree as well.
  await page.evaluate((t) => window.jetrace.seek(t), s.lastTick);
  await page.evaluate((t) => window.jetrace.seek(t), tick);
  s = await page.evaluate(() => window.jetrace.state());
  samePositions(s.cars, expected, 'seek back from the last tick');
  samePositions(s.ghosts[0], expectedGhost, 'ghost after seek back');

  for (const mode of ['top', 'chase', 'orbit']) {
    await page.select('#camera-mode', mode);
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const png = await page.screenshot({ path: mode === 'top' ? shotPath : undefined,
      clip: { x: 320, y: 120, width: 640, height: 440 } });
    const colours = await distinctColours(page, png);
    check(colours > 50, `${mode} camera: the 3D view is not blank (${colours} distinct colours)`);
  }

  // A second page plays; malformed messages close only the socket that sent them.
  const other = await openPage(browser);
  await other.evaluate(() => window.jetrace.play());
  const codes = [];
  for (const [payload, binary] of [['{not json', false], ['{"type":"seek","tick":-1}', false],
    ['{"type":"speed","value":9}', false], ['{"type":"play","x":1}', false], ['', true]]) {
    codes.push(await malformed(other, payload, binary));
  }
  check(codes.every((c) => c !== 1000 && c >= 1002), `malformed messages closed their sockets (codes ${codes.join(', ')})`);
  // Two pages and a third socket are open: a fourth is refused (--max-pages 3).
  const held = await other.evaluate(() => new Promise((resolve) => {
    window.held = new WebSocket('ws://' + location.host + '/ws');
    window.held.onopen = () => resolve(true);
    window.held.onclose = () => resolve(false);
  }));
  const refused = await malformed(other, '{"type":"play"}', false);
  check(held && refused === 1006, `a page over --max-pages is refused (close code ${refused})`);
  await other.evaluate(() => new Promise((resolve) => { window.held.onclose = resolve; window.held.close(); }));
  await page.evaluate(() => window.jetrace.sendRaw('{"type":"seek","tick":1e999}'));
  // Polled by a timer: the first page is a background tab now, where
  // requestAnimationFrame (puppeteer's default polling) does not run.
  await page.waitForFunction(() => window.jetrace.state().closed, { ...guard, polling: 100 });
  check(true, 'the first page was closed after its malformed seek');
  const before = await other.evaluate(() => window.jetrace.state());
  console.log(`second page at tick ${before.tick}, ${before.frames} frames, playing ${before.playing}`);
  await other.waitForFunction((n) => window.jetrace.state().frames > n + 5, guard, before.frames);
  const o = await other.evaluate(() => window.jetrace.state());
  check(o.connected && !o.closed && o.playing, 'the second page stays connected and keeps receiving frames');
} finally {
  await browser.close();
}
