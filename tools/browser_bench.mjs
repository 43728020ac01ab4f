// The browser player's figures (tools/browser_bench.sh): in headless
// Chromium, from opening the page jetrace-server --web serves to its first
// drawn frame, the bytes it downloads, input to display, and the bytes per
// second of a racing page; N pages that hold no keys; a replay verified by
// the WebAssembly client.
// Prints one JSON line per figure.
// Usage: node browser_bench.mjs drive URL | pages URL N MAX_SECONDS | verify URL REPLAY ROUNDS JETRACE_VERIFY
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { launchChromium } from '../tests/browser/page_checks.mjs';
import { hold, keysFor } from '../tests/browser/drive_keys.mjs';

const [mode, url, a3, a4] = process.argv.slice(2);
const guard = { timeout: 120000 };
const state = (page) => page.evaluate(() => window.jetrace.state());
const own = (s) => s.cars.find((c) => c.slot === s.ownSlot);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const median = (v) => { const s = [...v].sort((x, y) => x - y); return s.length ? s[Math.floor(s.length / 2)] : null; };
const round = (x, d = 1) => Math.round(x * 10 ** d) / 10 ** d;

async function drive(browser) {
  const page = await browser.newPage();
  const bytes = { page: 0, three: 0, wasm: 0 };
  page.on('response', async (r) => {
    try {
      // What crossed the wire: Content-Length (gzip-compressed where the server compressed).
      const n = Number(r.headers()['content-length'] || (await r.buffer()).length);
      const path = new URL(r.url()).pathname;
      if (path.startsWith('/three/')) bytes.three += n;
      else bytes.page += n;
    } catch { /* redirects and the like carry no body */ }
  });
  const opened = Date.now();
  await page.goto(url + '?name=bench', { waitUntil: 'load' });
  await page.waitForFunction(() => window.jetrace && window.jetrace.state().firstDrawMs !== null, guard);
  let s = await state(page);
  // The worker's fetches (jetrace_web.js and .wasm) are not the page's responses.
  for (const f of ['jetrace_web.js', 'jetrace_web.wasm']) {
    const r = await fetch(url + f, { headers: { 'Accept-Encoding': 'gzip' } });
    bytes.wasm += Number(r.headers.get('content-length'));
  }
  console.log(JSON.stringify({ figure: 'browser_first_frame', ms_to_first_drawn_frame: round(s.firstDrawMs),
    bytes_page: bytes.page, bytes_three: bytes.three, bytes_wasm: bytes.wasm,
    bytes_protocol_to_first_frame: s.traffic.bytes_down }));
  while (s.phase !== 'racing') { await sleep(20); s = await state(page); }
  // Input to display, 10 times: a steering key's event to the first draw of
  // a frame the client ticked with it.
  const probes = [];
  for (let i = 0; i < 10; i++) {
    const key = i % 2 ? 'ArrowRight' : 'ArrowLeft';
    await page.evaluate((steer) => window.jetrace.armInput({ throttle: 0, steer }), i % 2 ? 15 : -15);
    await page.keyboard.down(key);
    probes.push(await page.evaluate(() => window.jetrace.inputResult()));
    await page.keyboard.up(key);
    await sleep(150);
  }
  console.log(JSON.stringify({ figure: 'browser_input_to_display', probes: probes.length,
    draws_median: median(probes.map((p) => p.draws)), draws_max: Math.max(...probes.map((p) => p.draws)),
    ms_median: round(median(probes.map((p) => p.ms))), ms_max: round(Math.max(...probes.map((p) => p.ms))) }));
  const gates = await page.evaluate(() => window.jetrace.gates());
  const t0 = Date.now(), traffic0 = s.traffic;
  const held = new Set();
  while (Date.now() - t0 < 150000) {
    s = await state(page);
    const car = own(s);
    if (!car) continue;
    if (s.standings.find((r) => r.slot === s.ownSlot)?.finished) break;
    await hold(page, held, keysFor(car, gates));
  }
  await hold(page, held, new Set());
  const secs = (Date.now() - t0) / 1000, t = s.traffic;
  console.log(JSON.stringify({ figure: 'browser_player_bandwidth', cars: s.cars.length, seconds: round(secs),
    kbit_s_down: round((t.bytes_down - traffic0.bytes_down) * 8 / secs / 1000, 2),
    kbit_s_up: round((t.bytes_up - traffic0.bytes_up) * 8 / secs / 1000, 2),
    kbit_s_down_whole_session: round(t.bytes_down * 8 / ((Date.now() - opened) / 1000) / 1000, 2),
    corrections: s.net.corrections, snapshots: s.net.snapshots,
    finished: Boolean(s.standings.find((r) => r.slot === s.ownSlot)?.finished) }));
}

async function pages(browser, n, seconds) {
  const list = [];
  for (let i = 0; i < n; i++) {
    const page = await browser.newPage();
    await page.goto(url + '?name=page' + i, { waitUntil: 'load' });
    list.push(page);
  }
  for (const p of list) await p.waitForFunction(() => window.jetrace && window.jetrace.state().frames > 0, guard);
  // Until the race is over (every page closed by the server) or `seconds`.
  for (const t0 = Date.now(); Date.now() - t0 < seconds * 1000;) {
    // A page that is gone counts as closed.
    const closed = await Promise.all(list.map((p) => p.evaluate(() => window.jetrace.state().closed).catch(() => true)));
    if (closed.every(Boolean)) break;
    await sleep(500);
  }
}

// The replay verified in the page (the WebAssembly client, on the main
// thread) and by `native` (jetrace-verify FILE), alternately, `rounds`
// times each after one page round that is reported apart (Chromium's
// baseline code before its optimised code).
async function verify(browser, replayPath, rounds, native) {
  const page = await browser.newPage();
  await page.goto(url + '?watch', { waitUntil: 'load' });
  const b64 = readFileSync(replayPath).toString('base64');
  await page.evaluate(async (data) => {
    const create = (await import('/jetrace_web.js')).default;
    const M = await create({ locateFile: (p) => '/' + p });
    const bytes = Uint8Array.from(atob(data), (c) => c.charCodeAt(0));
    window.benchVerify = () => {
      const p = M._malloc(bytes.length);
      M.HEAPU8.set(bytes, p);
      const r = JSON.parse(M.UTF8ToString(M._jr_bench_verify(p, bytes.length)));
      M._free(p);
      return r;
    };
  }, b64);
  const first = await page.evaluate(() => window.benchVerify());
  const wasm = [], nat = [];
  for (let i = 0; i < Number(rounds); i++) {
    nat.push(JSON.parse(execFileSync(native, [replayPath]).toString()).wall_ms);
    const r = await page.evaluate(() => window.benchVerify());
    if (!r.ok || r.state_hash !== first.state_hash) throw new Error('the page did not verify the replay');
    wasm.push(r.wall_ms);
  }
  const w = median(wasm), n = median(nat);
  console.log(JSON.stringify({ figure: 'browser_wasm_verify', ok: first.ok, state_hash: first.state_hash,
    wasm_chromium_first_ms: round(first.wall_ms), wasm_chromium_ms_median: round(w), native_ms_median: round(n),
    wasm_over_native: round(w / n, 2), rounds: wasm.length }));
}

const browser = await launchChromium();
try {
  if (mode === 'drive') await drive(browser);
  else if (mode === 'pages') await pages(browser, Number(a3), Number(a4));
  else if (mode === 'verify') await verify(browser, a3, a4, process.argv[6]);
  else throw new Error('mode: drive, pages or verify');
} finally {
  await browser.close();
}
