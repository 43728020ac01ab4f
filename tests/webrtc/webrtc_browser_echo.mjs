// Headless Chromium against jetrace::webrtc's blocks (webrtc_echo_peer):
// the page offers an unreliable (ordered: false, maxRetransmits: 0) and a
// reliable data channel, the peer answers (ICE-lite, DTLS passive), and
// Chromium's own ICE, DTLS (BoringSSL), SCTP (dcsctp) and DCEP must open
// both channels; then 100 binary messages each way on each channel, one
// near the datagram budget, and a string. With LOSS (e.g. 0.2) the peer
// drops that share of the datagrams each way once the channels are open:
// every reliable message must still come back, in order, and the
// unreliable channel must not have resent what was lost (PR-SCTP with
// maxRetransmits 0 both ways, usrsctp against Chromium's dcsctp).
// Usage: node webrtc_browser_echo.mjs ECHO_PEER [LOSS]
import { spawn } from 'node:child_process';
import { check, launchChromium } from '../browser/page_checks.mjs';

const [peerPath, lossText] = process.argv.slice(2);
const loss = Number(lossText || 0);
const guard = { timeout: 20000 };  // a bound on waiting, not a timed assertion

function readAnswer(stream) {
  return new Promise((resolve, reject) => {
    let text = '';
    stream.on('data', (chunk) => {
      text += chunk;
      const end = text.indexOf('END\n');
      if (end >= 0) resolve(text.slice(0, end));
    });
    stream.on('end', () => reject(new Error(`the peer printed no answer: ${text}`)));
  });
}

const browser = await launchChromium();
const peer = spawn(peerPath, ['40', String(loss)], { stdio: ['pipe', 'pipe', 'inherit'] });
try {
  const page = await browser.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto('about:blank');
  const offer = await page.evaluate(async () => {
    const pc = new RTCPeerConnection();
    window.pc = pc;
    window.channels = {
      unreliable: pc.createDataChannel('unreliable', { ordered: false, maxRetransmits: 0 }),
      reliable: pc.createDataChannel('reliable'),
    };
    window.got = { unreliable: [], reliable: [], text: [] };
    for (const [name, channel] of Object.entries(window.channels)) {
      channel.binaryType = 'arraybuffer';
      channel.onmessage = (e) => {
        if (typeof e.data === 'string') window.got.text.push(e.data);
        else window.got[name].push(Array.from(new Uint8Array(e.data).slice(0, 2)).concat(e.data.byteLength));
      };
    }
    const o = await pc.createOffer();
    await pc.setLocalDescription(o);
    return o.sdp;
  });
  peer.stdin.end(offer);
  const answer = await readAnswer(peer.stdout);
  check(answer.includes('a=ice-lite'), 'the answer is ICE-lite');
  await page.evaluate((sdp) => window.pc.setRemoteDescription({ type: 'answer', sdp }), answer);
  const opened = Date.now();
  await page.waitForFunction(() => Object.values(window.channels).every((c) => c.readyState === 'open'), guard);
  console.log(`both channels open ${Date.now() - opened} ms after the answer`);
  await page.evaluate(() => {
    for (let i = 0; i < 100; ++i) {
      for (const [name, size] of [['unreliable', 200], ['reliable', 300]]) {
        const b = new Uint8Array(size);
        b[0] = i;
        b[1] = name === 'reliable' ? 1 : 0;
        window.channels[name].send(b);
      }
    }
    const big = new Uint8Array(1100);
    big[0] = 200;
    window.channels.reliable.send(big);
    window.channels.reliable.send('text on the reliable channel');
  });
  await page.waitForFunction(() => window.got.reliable.length === 101 && window.got.text.length === 1, guard);
  await new Promise((r) => setTimeout(r, loss > 0 ? 3000 : 500));  // time for any resend that should not come
  const got = await page.evaluate(() => window.got);
  const order = got.reliable.map((m) => m[0]);
  check(JSON.stringify(order.slice(0, 100)) === JSON.stringify([...Array(100).keys()]), 'reliable echoes in order');
  check(got.reliable[100][2] === 1100, 'the 1,100-byte message came back whole');
  check(got.text[0] === 'text on the reliable channel', 'the string came back as a string');
  if (loss > 0) {
    // Each echo crosses twice: about (1 - loss)^2 of them come back, never all.
    const expected = 100 * (1 - loss) * (1 - loss);
    check(got.unreliable.length < 100 && got.unreliable.length > expected / 2,
      `unreliable echoes: ${got.unreliable.length} of 100 at ${loss * 100} % loss each way (about ${expected.toFixed(0)} expected, lost ones never resent)`);
  } else {
    check(got.unreliable.length >= 90, `unreliable echoes: ${got.unreliable.length} of 100 on loopback`);
  }
  check(got.unreliable.every((m) => m[1] === 0 && m[2] === 200), 'unreliable echoes on their own channel');
  const stats = await page.evaluate(async () => {
    const out = {};
    (await window.pc.getStats()).forEach((r) => {
      if (r.type === 'transport') out.dtls = `${r.tlsVersion} ${r.dtlsCipher} ${r.dtlsState}`;
    });
    return out;
  });
  console.log(`chromium's view of the transport: ${stats.dtls}`);
  console.log('webrtc browser echo: ok');
} finally {
  peer.kill();
  await browser.close();
}
