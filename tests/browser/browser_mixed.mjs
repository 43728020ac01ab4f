// A mixed race (see browser_mixed.sh): 4 pages race 4 jetrace-bot drivers
// on one server, each page driven by its own follow-the-gates player.
// Every page must finish, and draw its car off the server's position only
// near another car or after a late input.
// Usage: node browser_mixed.mjs BASE_URL PAGES
import { check, launchChromium } from './page_checks.mjs';
import { hold, keysFor } from './drive_keys.mjs';

const [base, count] = process.argv.slice(2);
// Polled by timer: rAF polling stalls in pages that are not in front.
const guard = { timeout: 120000, polling: 100 };
const state = (page) => page.evaluate(() => window.jetrace.state());
const own = (s) => s.cars.find((c) => c.slot === s.ownSlot);

async function race(page, name) {
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().phase === 'racing', guard);
  const gates = await page.evaluate(() => window.jetrace.gates());
  const held = new Set();
  for (const t0 = Date.now(); Date.now() - t0 < 150000;) {
    const s = await state(page);
    const car = own(s);
    if (!car) continue;
    const mine = s.standings.find((r) => r.slot === s.ownSlot);
    if (mine && mine.finished) {
      await hold(page, held, new Set());
      const n = s.net;
      return { name, finished: true, transport: s.transport, time_s: mine.finish_s, corrections: n.corrections, late_inputs: n.late_inputs,
        drawn_checked: n.drawn_checked, drawn_off: n.drawn_off, drawn_off_unexplained: n.drawn_off_unexplained };
    }
    await hold(page, held, keysFor(car, gates));
  }
  return { name, finished: false };
}

const browser = await launchChromium();
try {
  const pages = [];
  for (let i = 0; i < Number(count); i++) {
    const page = await browser.newPage();
    // Small views: four pages draw in software on one machine.
    await page.setViewport({ width: 480, height: 300 });
    page.on('pageerror', (e) => console.log(`page${i} error: ${e.message}`));
    await page.goto(`${base}?name=page${i}`, { waitUntil: 'load' });
    pages.push(page);
  }
  const results = await Promise.all(pages.map((p, i) => race(p, 'page' + i)));
  for (const r of results) console.log(JSON.stringify(r));
  check(results.every((r) => r.finished), `every page finished (${results.filter((r) => r.finished).length} of ${results.length})`);
  // 4 pages from one address: within the data channel's pending cap (4).
  check(results.every((r) => r.transport === 'webrtc'),
    `every page raced over its WebRTC data channel (${results.map((r) => r.transport).join(', ')})`);
  check(results.every((r) => r.drawn_checked > 100 && r.drawn_off_unexplained === 0),
    'every page drew its car where the server had it but near another car or after a late input');
} finally {
  await browser.close();
}
