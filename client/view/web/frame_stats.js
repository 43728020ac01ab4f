// The page's own timing, for benchmarks (tools/view_bench.mjs): how long each
// draw (renderer.render + labels.render) took, the interval between drawn
// frames (requestAnimationFrame callbacks that drew), how long handling each
// message took (parse, place the cars, the panels), and the messages and bytes
// received. Off until measure() starts it; then two performance.now() calls
// per draw and per message, into fixed rings.
const RING = 4096;

export class FrameStats {
  constructor() {
    this.on = false;
    this.render = new Float64Array(RING);
    this.interval = new Float64Array(RING);
    this.handle = new Float64Array(RING);
    this.reset();
  }

  // Starts (or restarts) measuring from now.
  reset() {
    this.draws = 0;
    this.messages = 0;
    this.bytes = 0;
    this.lastDraw = null;
    this.intervals = 0;
    this.start = performance.now();
  }

  measure(on) {
    this.on = on;
    this.reset();
  }

  // Wraps one draw: `fn` is the render.
  draw(fn) {
    if (!this.on) return fn();
    const t0 = performance.now();
    fn();
    const t1 = performance.now();
    this.render[this.draws % RING] = t1 - t0;
    this.draws++;
    if (this.lastDraw !== null) this.interval[this.intervals++ % RING] = t0 - this.lastDraw;
    this.lastDraw = t0;
    return undefined;
  }

  // Wraps the handling of a message of `chars` characters (UTF-16 units; the
  // frames are ASCII but for names, so about bytes).
  message(chars, fn) {
    if (!this.on) return fn();
    const t0 = performance.now();
    fn();
    this.handle[this.messages % RING] = performance.now() - t0;
    this.messages++;
    this.bytes += chars;
    return undefined;
  }

  // The last (up to RING) draws and intervals (ms), and the counts since measure().
  report() {
    const last = (ring, n) => {
      const k = Math.min(n, RING);
      const out = [];
      for (let i = n - k; i < n; i++) out.push(ring[i % RING]);
      return out;
    };
    return {
      measuring: this.on, elapsed_ms: performance.now() - this.start, draws: this.draws,
      messages: this.messages, message_bytes: this.bytes,
      render_ms: last(this.render, this.draws), interval_ms: last(this.interval, this.intervals),
      message_ms: last(this.handle, this.messages),
    };
  }
}
