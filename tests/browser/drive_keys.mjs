// The drive tests' player: keys held through puppeteer, and the
// follow-the-gates helper that chooses them from what the page shows.
// Holds exactly the keys in `want` (KeyboardEvent codes).
export async function hold(page, held, want) {
  for (const k of [...held]) if (!want.has(k)) { await page.keyboard.up(k); held.delete(k); }
  for (const k of want) if (!held.has(k)) { await page.keyboard.down(k); held.add(k); }
}

// The follow-the-gates helper: up always; left or right toward the next
// gate's centre (in the horizontal plane), the brake in a sharp turn at speed.
export function keysFor(car, gates) {
  const g = gates[car.gate];
  const dx = g.center[0] - car.x, dz = g.center[2] - car.z;
  const len = Math.hypot(dx, dz) || 1;
  const [fx, , fz] = car.f;
  // right = forward x up (up = +y), as the core's driving AI has it.
  const rx = -fz, rz = fx;
  const lateral = (dx * rx + dz * rz) / len, ahead = (dx * fx + dz * fz) / len;
  const want = new Set(['ArrowUp']);
  if (ahead < 0 || lateral > 0.08) want.add(lateral >= 0 ? 'ArrowRight' : 'ArrowLeft');
  else if (lateral < -0.08) want.add('ArrowLeft');
  if ((ahead < 0.5 && car.speed > 25) || ahead < 0) want.add('Space');
  return want;
}
