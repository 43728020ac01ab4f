// Drives a car from jetrace-view's page in headless Chromium (see
// viewer_drive.sh): presses the keys a player would, steering toward the
// next gate the page's state hook shows, until the car finishes.
// Usage: node viewer_drive.mjs URL SHOT.png
import { check, distinctColours, launchChromium } from './page_checks.mjs';
import { hold, keysFor } from './drive_keys.mjs';

const [url, shotPath] = process.argv.slice(2);
const guard = { timeout: 90000 };  // a bound on waiting, not a timed assertion

const state = (page) => page.evaluate(() => window.jetrace.state());
const own = (s) => s.cars.find((c) => c.slot === s.ownSlot);

const browser = await launchChromium();
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log('page error: ' + e.message));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().frames > 0, guard);
  const gates = await page.evaluate(() => window.jetrace.gates());
  let s = await state(page);
  check(s.mode === 'drive' && s.ownSlot >= 0, `drive mode, the own car's slot ${s.ownSlot}`);
  // The race starts by the server's lobby timeout, usually after the page
  // loaded: then the page shows the lobby, the countdown's seconds, racing.
  const phases = [s.phase];
  let counted = 0;
  for (let t0 = Date.now(); s.phase !== 'racing' && Date.now() - t0 < guard.timeout;) {
    await new Promise((r) => setTimeout(r, 50));
    s = await state(page);
    if (phases[phases.length - 1] !== s.phase) phases.push(s.phase);
    if (s.phase === 'countdown' && s.countdown > 0) counted = Math.max(counted, s.countdown);
  }
  console.log(`phases shown: ${phases.join(' -> ')}; countdown up to ${counted} s`);
  check(s.phase === 'racing', 'the race started');
  check(own(s) !== undefined, 'the own car is shown');
  check(s.standings.some((r) => r.name === 'human'), 'the standings name the driver');
  check(s.standings.some((r) => r.name === 'robot0'), 'and the bot');
  check(s.cars.length === 2, 'both cars are shown');
  if (phases[0] === 'lobby') {
    check(phases.join() === 'lobby,countdown,racing' && counted > 0.5, 'lobby, then the countdown\'s seconds, then racing');
  }

  const held = new Set();
  const botAt = (x) => x.cars.find((c) => c.slot !== x.ownSlot);
  const botStart = botAt(s);
  let top = 0, steps = 0, botMoved = false;
  const start = Date.now();
  while (Date.now() - start < 120000) {
    s = await state(page);
    const car = own(s);
    if (!car) continue;
    top = Math.max(top, car.speed);
    const b = botAt(s);
    if (b && botStart && Math.hypot(b.x - botStart.x, b.z - botStart.z) > 50) botMoved = true;
    if (s.standings.find((r) => r.slot === s.ownSlot)?.finished) break;
    await hold(page, held, keysFor(car, gates));
    if (++steps % 40 === 0) console.log(`tick ${s.tick} lap ${car.lap} gate ${car.gate} speed ${car.speed}`);
  }
  await hold(page, held, new Set());
  s = await state(page);
  const mine = s.standings.find((r) => r.slot === s.ownSlot);
  check(top > 20, `the car accelerated with the up key (top speed ${top} m/s)`);
  check(mine && mine.finished, `the human car finished the lap (${mine ? mine.finish_s : '?'} s, ${steps} steering steps)`);
  check(s.keys && !s.keys.up && !s.keys.left && !s.keys.right && !s.keys.brake, 'the keys are released');
  check(botMoved, `the bot's car moved on the page (${botMoved ? 'yes' : 'no'})`);
  const png = await page.screenshot({ path: shotPath, clip: { x: 320, y: 120, width: 640, height: 440 } });
  const colours = await distinctColours(page, png);
  check(colours > 50, `the 3D view is not blank (${colours} distinct colours)`);

  // A malformed keys message closes that page's socket.
  await page.evaluate(() => window.jetrace.sendRaw('{"type":"keys","up":1,"left":false,"right":false,"brake":false}'));
  await page.waitForFunction(() => window.jetrace.state().closed, guard);
  check(true, 'a malformed keys message closed the page socket');
} finally {
  await browser.close();
}
