// Drive mode: the keyboard state (arrows or WASD, space or down to brake)
// sent to jetrace-view whenever it changes; released when the page loses
// the focus.
const KEYS = {
  ArrowUp: 'up', KeyW: 'up', ArrowLeft: 'left', KeyA: 'left', ArrowRight: 'right', KeyD: 'right',
  ArrowDown: 'brake', KeyS: 'brake', Space: 'brake',
};

export function driveKeys(send) {
  const held = new Set();
  let last = '';
  const current = () => {
    const k = { type: 'keys', up: false, left: false, right: false, brake: false };
    for (const code of held) k[KEYS[code]] = true;
    return k;
  };
  const flush = () => {
    const k = current();
    const text = JSON.stringify(k);
    if (text === last) return;
    last = text;
    send(k);
  };
  const on = (down) => (e) => {
    if (!(e.code in KEYS)) return;
    e.preventDefault();
    if (down) held.add(e.code); else held.delete(e.code);
    flush();
  };
  window.addEventListener('keydown', on(true));
  window.addEventListener('keyup', on(false));
  window.addEventListener('blur', () => { held.clear(); flush(); });
  return { current };
}
