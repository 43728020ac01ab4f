// A private race from the page (see browser_private.sh): a page whose URL
// fragment carries a valid connect token joins under the token's name; one
// with a token signed by another key is refused, and shows why.
// Usage: node browser_private.mjs BASE_URL GOOD_TOKEN BAD_TOKEN
import { check, launchChromium } from './page_checks.mjs';

const [base, good, bad] = process.argv.slice(2);
const guard = { timeout: 90000 };
const browser = await launchChromium();
try {
  const page = await browser.newPage();
  await page.goto(base + '#token=' + good, { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().frames > 0, guard);
  const s = await page.evaluate(() => window.jetrace.state());
  check(s.mode === 'drive' && s.ownSlot >= 0, `the page with a valid token joined (slot ${s.ownSlot})`);
  check(s.driver === 'alice', `under the name the token was issued to (${s.driver})`);

  const refused = await browser.newPage();
  await refused.goto(base + '#token=' + bad, { waitUntil: 'load' });
  await refused.waitForFunction(() => window.jetrace && window.jetrace.state().closed, guard);
  const r = await refused.evaluate(() => window.jetrace.state());
  check(/code 2001/.test(r.closeText) && /token/.test(r.closeText), `a bad token is refused and the page says so: "${r.closeText}"`);
  const shown = await refused.evaluate(() => document.getElementById('closed-text').textContent);
  check(shown === r.closeText, 'the reason is on the page');
} finally {
  await browser.close();
}
