// What the browser tests share: headless Chromium from Debian driven by
// puppeteer-core, a failing check that names what it expected, and the
// number of distinct colours in a screenshot (a blank view has a handful).
import puppeteer from 'puppeteer-core';

export function check(ok, what) {
  if (!ok) throw new Error('FAILED: ' + what);
  console.log('ok: ' + what);
}

// Chromium's start (SwiftShader, a fresh profile) took over puppeteer's
// default 30 s once on a loaded 2-core machine: it is given longer.
export function launchChromium(extraArgs = []) {
  return puppeteer.launch({
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--window-size=1280,720', ...extraArgs],
    defaultViewport: { width: 1280, height: 720 },
    timeout: 120000,
    protocolTimeout: 120000,
  });
}

// Decodes `png` in `page` and counts its distinct RGB colours.
export async function distinctColours(page, png) {
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = 'data:image/png;base64,' + b64;
    await img.decode();
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size;
  }, Buffer.from(png).toString('base64'));
}
