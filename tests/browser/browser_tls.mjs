// The page over HTTPS and its game socket over WSS (see browser_tls.sh):
// Chromium trusts the test's self-signed certificate by its SPKI hash.
// Usage: node browser_tls.mjs HTTPS_URL SPKI_SHA256_BASE64
import { check, launchChromium } from './page_checks.mjs';

const [url, spki] = process.argv.slice(2);
const browser = await launchChromium(['--ignore-certificate-errors-spki-list=' + spki]);
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log('page error: ' + e.message));
  await page.goto(url + '?name=secure', { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().frames > 0, { timeout: 90000, polling: 100 });
  const s = await page.evaluate(() => window.jetrace.state());
  check(s.source === 'client' && s.mode === 'drive' && s.ownSlot >= 0, `the https page joined over wss (slot ${s.ownSlot})`);
  check(await page.evaluate(() => location.protocol) === 'https:', 'the page came over https');
} finally {
  await browser.close();
}
