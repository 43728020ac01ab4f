// The player's panels on the page jetrace-server serves: the join form (a
// name, race or watch), and while driving the speed, lap, lap time,
// position and the connection (round trip, corrections); a close shows its
// reason. ?name=NAME joins at once, ?watch watches, #token=HEX (the URL
// fragment: never sent to a server) joins a private race.
const $ = (id) => document.getElementById(id);

// A connect token as jetrace-token prints it (unpadded URL-safe base64):
// its bytes in hex and the name it was issued to (docs/PROTOCOL.md,
// "Connect tokens": version, name length, name, ...); null if it is not one.
export function readToken(text) {
  if (!/^[A-Za-z0-9_-]{1,250}$/.test(text)) return null;
  let bytes;
  try {
    const b64 = text.replace(/-/g, '+').replace(/_/g, '/');
    bytes = Uint8Array.from(atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4)), (c) => c.charCodeAt(0));
  } catch {
    return null;
  }
  if (bytes.length < 3 || bytes[0] !== 1 || bytes[1] > 32 || bytes.length < 2 + bytes[1]) return null;
  const name = new TextDecoder().decode(bytes.subarray(2, 2 + bytes[1]));
  return { hex: [...bytes].map((x) => x.toString(16).padStart(2, '0')).join(''), name };
}

function joinOptions() {
  const q = new URLSearchParams(location.search);
  const fragment = new URLSearchParams(location.hash.slice(1));
  const o = { name: q.get('name'), watch: q.has('watch'), token: '', tokenError: null,
    transport: q.get('transport') === 'websocket' ? 'websocket' : null };
  const text = fragment.get('token');
  if (text !== null) {
    const t = readToken(text);
    // A private race's player joins under the name the token was issued to.
    if (t) Object.assign(o, { token: t.hex, name: t.name, watch: false });
    else o.tokenError = 'the connect token in the URL is not one (jetrace-token issue prints them)';
  }
  return o;
}

// How the HUD names the page's transport (client_source.js chooses it).
const kTransportNames = { webrtc: 'WebRTC', websocket: 'WebSocket' };

export class Hud {
  constructor() {
    this.hello = null;
    this.lap = null;
    this.lapStart = 0;
    this.source = null;
  }

  // Resolves with the client source once the player chose a name (or the URL did).
  async join() {
    const o = joinOptions();
    if (o.tokenError) {
      this.setClosed(o.tokenError);
      throw new Error(o.tokenError);
    }
    if (o.name === null && !o.watch) {
      const form = $('join');
      form.hidden = false;
      $('join-name').value = localStorage.getItem('jetrace-name') || '';
      $('join-name').focus();
      o.watch = await new Promise((resolve) => {
        form.addEventListener('submit', (e) => { e.preventDefault(); resolve(e.submitter && e.submitter.value === 'watch'); });
      });
      o.name = $('join-name').value.trim() || 'player';
      localStorage.setItem('jetrace-name', o.name);
      form.hidden = true;
    }
    if (o.name === null) o.name = 'watcher';
    $('track').textContent = 'joining…';
    const { clientSource } = await import('./client_source.js');
    this.source = clientSource(o);
    return this.source;
  }

  setHello(h) {
    this.hello = h;
    $('hud').hidden = h.mode !== 'drive';
  }

  setFrame(f) {
    if (!this.hello || this.hello.mode !== 'drive') return;
    const own = f.cars.find((c) => c.slot === f.own_slot);
    const row = f.standings.find((s) => s.slot === f.own_slot);
    if (own) {
      if (own.lap !== this.lap) { this.lap = own.lap; this.lapStart = Math.max(0, f.race_s); }
      $('hud-speed').textContent = Math.round(own.speed * 3.6) + ' km/h';
      $('hud-lap').textContent = 'lap ' + Math.min(own.lap + 1, f.laps) + '/' + f.laps;
      $('hud-laptime').textContent = row && row.finished ? 'finished ' + row.finish_s.toFixed(3) + ' s'
        : (Math.max(0, f.race_s - this.lapStart)).toFixed(2) + ' s';
    }
    if (row) $('hud-pos').textContent = 'P' + row.pos + '/' + f.standings.length;
    if (f.net) {
      const t = this.source ? this.source.transport() : null;
      $('hud-net').textContent = (t ? kTransportNames[t] + ' · ' : '') + 'rtt ' + Math.round(f.net.rtt_ms) + ' ms' +
        (f.net.corrections ? ' · ' + f.net.corrections + ' corrections (largest ' + f.net.max_correction_m.toFixed(2) + ' m)' : '');
    }
    $('hud-countdown').textContent = f.countdown_s !== null && f.countdown_s !== undefined ? Math.ceil(f.countdown_s) : '';
  }

  setClosed(text) {
    $('closed').hidden = false;
    $('closed-text').textContent = text;
  }
}
