// The honest page of browser_rtc_flood.sh: it joins over its WebRTC data
// channel while the flood's handshakes are pending, and the metrics count
// the flood's refusals.
// Usage: node browser_rtc_flood.mjs BASE_URL METRICS_URL
import { check, launchChromium } from './page_checks.mjs';

const [base, metricsUrl] = process.argv.slice(2);
const browser = await launchChromium();
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(base + '?name=honest', { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().frames > 0, { timeout: 90000 });
  const s = await page.evaluate(() => window.jetrace.state());
  check(s.mode === 'drive' && s.ownSlot >= 0, `the honest page joined (mode ${s.mode}, slot ${s.ownSlot})`);
  check(s.transport === 'webrtc', `over its WebRTC data channel (${s.transport}${s.transportWhy ? ': ' + s.transportWhy : ''})`);
  const metrics = await (await fetch(metricsUrl)).text();
  const value = (re) => Number((metrics.match(re) || [])[1]);
  const busy = value(/jetrace_webrtc_refused_total\{reason="busy"\} (\S+)/);
  const players = value(/jetrace_transport_players\{transport="webrtc"\} (\S+)/);
  check(busy === 96 && players === 1, `the metrics: ${busy} offers refused busy, ${players} player over webrtc`);
} finally {
  await browser.close();
}
