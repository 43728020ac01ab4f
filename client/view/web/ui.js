// The panels: race status, standings, ghosts, the timeline and the camera
// choice. Fills them from hello and frame messages; sends what the user
// asks through `send`.
const $ = (id) => document.getElementById(id);

function seconds(v) {
  return v === null || v === undefined ? '—' : v.toFixed(3) + ' s';
}

function clock(s) {
  const sign = s < 0 ? '-' : '';
  const a = Math.abs(s), m = Math.floor(a / 60);
  return sign + m + ':' + (a - m * 60).toFixed(2).padStart(5, '0');
}

export class Panels {
  constructor(send, onCamera) {
    this.send = send;
    this.hello = null;
    this.playing = false;
    this.dragging = false;
    $('play').addEventListener('click', () => send({ type: this.playing ? 'pause' : 'play' }));
    $('speed').addEventListener('change', (e) => send({ type: 'speed', value: Number(e.target.value) }));
    const seek = $('seek');
    seek.addEventListener('input', () => { this.dragging = true; this.showTick(Number(seek.value)); });
    seek.addEventListener('change', () => { this.dragging = false; send({ type: 'seek', tick: Number(seek.value) }); });
    $('camera-mode').addEventListener('change', (e) => onCamera(e.target.value, Number($('camera-car').value)));
    $('camera-car').addEventListener('change', (e) => onCamera($('camera-mode').value, Number(e.target.value)));
  }

  setHello(h) {
    this.hello = h;
    this.laps = h.laps;
    this.showTrack();
    // Live races have no timeline.
    $('timeline').hidden = h.mode !== 'replay';
    $('mode').textContent = h.mode === 'drive' ? 'driving ' + h.driver + ' (arrows or WASD, space to brake)'
      : h.mode === 'live' ? 'watching live' : '';
    const seek = $('seek');
    seek.min = h.first_tick;
    seek.max = h.last_tick;
    const cars = $('camera-car');
    cars.replaceChildren(...h.cars.map((c) => new Option(c.name, c.slot)));
    $('ghosts').textContent = h.ghosts.length
      ? 'ghosts: ' + h.ghosts.map((g) => g.file.split('/').pop() + ' (' + g.cars.length + ' cars)').join(', ') : '';
  }

  showTrack() {
    $('track').textContent = this.hello.track.name + ' · ' + this.laps + (this.laps === 1 ? ' lap' : ' laps');
  }

  addCar(slot, name) {
    $('camera-car').append(new Option(name, slot));
  }

  setCamera(mode, slot) {
    $('camera-mode').value = mode;
    $('camera-car').value = String(slot);
  }

  showTick(tick) {
    const h = this.hello;
    if (!h || h.mode !== 'replay') return;
    $('seek-label').textContent = 'tick ' + tick + ' / ' + h.last_tick + ' · ' + clock((tick - h.start_tick) / h.tick_rate_hz);
  }

  setFrame(f, names) {
    this.playing = f.playing;
    $('play').textContent = f.playing ? 'pause' : 'play';
    if (f.laps !== undefined && f.laps !== this.laps) {
      this.laps = f.laps;
      this.showTrack();
    }
    $('phase').textContent = f.phase + (f.countdown_s !== undefined && f.countdown_s !== null
      ? ' ' + f.countdown_s.toFixed(1) + ' s' : '');
    if (f.connection !== undefined) this.setConnection(f.connection === 'connected' ? '' : f.connection);
    $('tick').textContent = f.tick;
    $('clock').textContent = clock(f.race_s);
    if (Number($('speed').value) !== f.speed) $('speed').value = String(f.speed);
    if (!this.dragging) {
      $('seek').value = f.tick;
      this.showTick(f.tick);
    }
    const rows = f.standings.map((s) => {
      const tr = document.createElement('tr');
      // A gap is negative when this car passed its last gate before the
      // leader did and the leader is nearer the next one now.
      const gap = s.finished ? seconds(s.finish_s) : s.pos === 1 ? 'leader' : s.gap_s === null ? '—'
        : (s.gap_s < 0 ? '−' + seconds(-s.gap_s) : '+' + seconds(s.gap_s));
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = names.color(s.slot);
      const cells = [String(s.pos), s.name, s.finished ? 'done' : s.lap + '/' + this.laps, gap, seconds(s.best_lap_s)];
      cells.forEach((text, i) => {
        const td = document.createElement('td');
        if (i === 1) td.append(swatch);
        td.append(text);
        tr.append(td);
      });
      return tr;
    });
    $('standings-body').replaceChildren(...rows);
  }

  setConnection(text) {
    $('conn').textContent = text;
  }
}
