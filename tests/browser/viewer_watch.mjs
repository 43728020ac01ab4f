// Watches a live race from jetrace-view's page in headless Chromium (see
// viewer_watch.sh): samples what the page shows while the cars race (the
// render tick, the two snapshot ticks it interpolates between, each car's
// position) for the script to check against the recorded race, and checks
// the page itself: watch mode, no own car, both cars and their names, a
// 3D view that is not blank.
// Writes READY once the page shows the lobby (the script then starts the bots).
// Usage: node viewer_watch.mjs URL SAMPLES.json SHOT.png READY
import { writeFileSync } from 'node:fs';
import { check, distinctColours, launchChromium } from './page_checks.mjs';

const [url, samplesPath, shotPath, readyPath] = process.argv.slice(2);
const guard = { timeout: 90000 };  // a bound on waiting, not a timed assertion

const browser = await launchChromium();
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log('page error: ' + e.message));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().frames > 0, guard);
  let s = await page.evaluate(() => window.jetrace.state());
  check(s.mode === 'live' && s.ownSlot === -1, `watch mode without a car of its own (mode ${s.mode}, slot ${s.ownSlot})`);
  writeFileSync(readyPath, 'ready\n');
  await page.waitForFunction(() => window.jetrace.state().phase === 'racing' &&
    window.jetrace.state().cars.length === 2, guard);

  // Samples while both cars race, about 0.6 s apart.
  const samples = [];
  const start = Date.now();
  while (samples.length < 10 && Date.now() - start < 60000) {
    s = await page.evaluate(() => window.jetrace.state());
    if (s.phase !== 'racing') break;
    const racing = s.standings.every((r) => !r.finished);
    if (racing && s.render && s.render.from !== null && s.cars.length === 2) {
      samples.push({ render: s.render, tick: s.tick, cars: s.cars.map((c) => ({ slot: c.slot, p: [c.x, c.y, c.z] })) });
    }
    await new Promise((r) => setTimeout(r, 600));
  }
  check(samples.length >= 4, `${samples.length} samples of the race in progress`);
  const ticks = samples.map((x) => x.render.tick);
  check(ticks.every((t, i) => i === 0 || t > ticks[i - 1]), `the render tick advances (${ticks.map((t) => t.toFixed(1)).join(', ')})`);
  writeFileSync(samplesPath, JSON.stringify(samples));

  check(s.standings.some((r) => r.name === 'robot0') && s.standings.some((r) => r.name === 'robot1'),
    'the standings name both bots');
  await page.evaluate(() => window.jetrace.camera('top'));
  await new Promise((r) => setTimeout(r, 300));
  const png = await page.screenshot({ path: shotPath });
  const colours = await distinctColours(page, png);
  check(colours > 50, `the 3D view is not blank (${colours} distinct colours)`);
} finally {
  await browser.close();
}
