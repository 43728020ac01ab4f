// One case of tools/view_bench.sh: PAGES pages of jetrace-view (started
// with --paused) in headless Chromium; once every page has drawn the track,
// all play from the first tick at 1x for SECONDS while each page times its
// own draws (window.jetrace.measure/frameTimes) and jetrace-view's process
// CPU time is read from /proc. Prints one JSON object.
// Usage: node view_bench.mjs URL VIEW_PID PAGES SECONDS
import { readFileSync } from 'node:fs';
import puppeteer from 'puppeteer-core';

const [url, viewPidText, pagesText, secondsText] = process.argv.slice(2);
const viewPid = Number(viewPidText), pageCount = Number(pagesText), seconds = Number(secondsText);
if (!url || !(viewPid > 0) || !(pageCount >= 1 && pageCount <= 16) || !(seconds > 0 && seconds <= 600)) {
  console.error('usage: node view_bench.mjs URL VIEW_PID PAGES(1..16) SECONDS(0..600]');
  process.exit(2);
}
const guard = { timeout: 300000, polling: 200 };  // a bound on waiting, not a timed assertion; timer-polled
const CLK_TCK = 100;                // Linux's USER_HZ for /proc/PID/stat

// jetrace-view's user + system CPU time (s), from /proc/PID/stat fields 14 and 15.
function cpuSeconds(pid) {
  const stat = readFileSync(`/proc/${pid}/stat`, 'utf8');
  const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');  // fields from 3 on
  return (Number(fields[11]) + Number(fields[12])) / CLK_TCK;
}

function quantile(values, q) {
  if (values.length === 0) return null;
  const s = [...values].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
}

const round = (x, digits = 3) => (x === null ? null : Number(x.toFixed(digits)));

// Each page in a window of its own: a background tab of a window is hidden
// and draws nothing (requestAnimationFrame does not run).
async function newWindowPage(browser, known) {
  const session = await browser.target().createCDPSession();
  await session.send('Target.createTarget', { url: 'about:blank', newWindow: true });
  await session.detach();
  const target = await browser.waitForTarget((t) => t.type() === 'page' && !known.has(t), guard);
  known.add(target);
  const page = await target.page();
  await page.setViewport({ width: 1280, height: 720 });
  return page;
}

async function openPage(browser, known) {
  const page = await newWindowPage(browser, known);
  page.on('pageerror', (e) => console.error('page error: ' + e.message));
  await page.goto(url, { waitUntil: 'load', timeout: guard.timeout });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().trackLoaded &&
    window.jetrace.state().frames > 0, guard);
  return page;
}

// One page's figures from its frameTimes() report.
function pageFigures(r) {
  const s = r.elapsed_ms / 1000;
  return {
    render_ms_median: round(quantile(r.render_ms, 0.5)), render_ms_p99: round(quantile(r.render_ms, 0.99)),
    frame_interval_ms_median: round(quantile(r.interval_ms, 0.5)),
    frame_interval_ms_p99: round(quantile(r.interval_ms, 0.99)),
    message_ms_median: round(quantile(r.message_ms, 0.5)), message_ms_p99: round(quantile(r.message_ms, 0.99)),
    fps: round(r.draws / s, 2), frames_received_per_s: round(r.messages / s, 2),
    ws_bytes_per_s: Math.round(r.message_bytes / s),
    ws_bytes_per_frame: r.messages ? Math.round(r.message_bytes / r.messages) : null, draws: r.draws,
  };
}

async function measure(pages) {
  for (const p of pages) await p.evaluate(() => window.jetrace.measure(true));  // paused at the first tick
  const cpu0 = cpuSeconds(viewPid), t0 = performance.now();
  for (const p of pages) await p.evaluate(() => window.jetrace.play());
  await new Promise((resolve) => setTimeout(resolve, seconds * 1000));
  const cpu1 = cpuSeconds(viewPid), wall = (performance.now() - t0) / 1000;
  const reports = [];
  for (const p of pages) reports.push(await p.evaluate(() => window.jetrace.frameTimes()));
  for (const p of pages) await p.evaluate(() => window.jetrace.pause());
  return { reports, cpu: cpu1 - cpu0, wall };
}

const browser = await puppeteer.launch({
  executablePath: '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=1280,720'],
  defaultViewport: { width: 1280, height: 720 },
  timeout: 120000,
  protocolTimeout: 300000,
});
try {
  const known = new Set(browser.targets()), pages = [];
  for (let i = 0; i < pageCount; i++) pages.push(await openPage(browser, known));
  const cars = (await pages[0].evaluate(() => window.jetrace.state().cars)).length;
  const { reports, cpu, wall } = await measure(pages);
  const perPage = reports.map(pageFigures);
  console.log(JSON.stringify({
    pages: pageCount, cars, seconds: round(wall, 2),
    view_cpu_s: round(cpu, 3), view_cpu_fraction: round(cpu / wall, 4),
    view_cpu_fraction_per_page: round(cpu / wall / pageCount, 4),
    ...perPage[0], per_page: perPage,
  }));
} finally {
  await browser.close();
}
