// The page's WebRTC data channels to jetrace-server (docs/PROTOCOL.md,
// "Transport: WebRTC data channel"; docs/BROWSER.md, "Transports").
// RTCPeerConnection exists on the main thread only, not in Web Workers, so
// this side makes it and the two channels: "unreliable" (unordered, no
// retransmissions) for channel 0 and "reliable" (ordered, reliable) for
// channel 1. The channels themselves go to the worker (RTCDataChannel is
// transferable in Chromium), so their messages never wait for the main
// thread's drawing; where a browser cannot transfer them, the main thread
// relays each frame (a channel byte and one message, as on the WebSocket).

// Opens both channels for `worker`: resolves with the link, or rejects with
// the reason (POST /rtc refused, or the channels not open within `timeoutMs`).
export async function openRtcLink(timeoutMs, worker) {
  if (typeof RTCPeerConnection !== 'function') throw new Error('no RTCPeerConnection in this browser');
  const pc = new RTCPeerConnection({ iceServers: [] });
  const channels = [
    pc.createDataChannel('unreliable', { ordered: false, maxRetransmits: 0 }),
    pc.createDataChannel('reliable', { ordered: true }),
  ];
  let moved = true;
  try {
    worker.postMessage({ type: 'rtc-channels', channels }, channels);
  } catch {
    moved = false;  // not transferable here: relayed by this thread
  }
  let timer = null, onWorker = null;
  try {
    const opened = moved ? new Promise((resolve, reject) => {
      onWorker = (e) => {
        if (e.data.type === 'rtc-opened') resolve();
        else if (e.data.type === 'rtc-close') reject(new Error('a data channel closed while opening'));
      };
      worker.addEventListener('message', onWorker);
    }) : Promise.all(channels.map((c) => new Promise((resolve, reject) => {
      c.onopen = resolve;
      c.onclose = () => reject(new Error('a data channel closed while opening'));
    })));
    const late = new Promise((_, reject) => {
      timer = setTimeout(() => reject(new Error('the data channels did not open within ' + timeoutMs + ' ms')), timeoutMs);
    });
    const signalled = (async () => {
      // An ICE-lite server learns the page's address from its STUN checks:
      // the offer goes at once, without waiting for candidates.
      await pc.setLocalDescription(await pc.createOffer());
      const r = await fetch('/rtc', { method: 'POST', headers: { 'Content-Type': 'application/sdp' },
        body: pc.localDescription.sdp });
      const text = await r.text();
      if (!r.ok) throw new Error('POST /rtc: HTTP ' + r.status + ' ' + text.trim());
      await pc.setRemoteDescription({ type: 'answer', sdp: text });
      await opened;
    })();
    await Promise.race([signalled, late]);
  } catch (e) {
    pc.close();
    if (moved) worker.postMessage({ type: 'rtc-drop' });
    throw e;
  } finally {
    clearTimeout(timer);
    if (onWorker) worker.removeEventListener('message', onWorker);
  }
  return moved ? { mode: 'worker', pc, close() { pc.close(); } } : relayLink(pc, channels, worker);
}

// The main thread carries the frames: worker <-> channels.
function relayLink(pc, channels, worker) {
  let closed = false;
  const close = () => {
    if (closed) return;
    closed = true;
    worker.postMessage({ type: 'rtc-close' });
  };
  channels.forEach((c, channel) => {
    c.binaryType = 'arraybuffer';
    c.onmessage = (e) => {
      if (!(e.data instanceof ArrayBuffer)) return;
      const frame = new Uint8Array(e.data.byteLength + 1);
      frame[0] = channel;
      frame.set(new Uint8Array(e.data), 1);
      worker.postMessage({ type: 'rtc-frame', frame: frame.buffer }, [frame.buffer]);
    };
    c.onclose = close;
  });
  pc.onconnectionstatechange = () => {
    if (pc.connectionState === 'failed' || pc.connectionState === 'closed') close();
  };
  return {
    mode: 'relay',
    pc,
    // One frame from the worker: its channel byte picks the data channel.
    send(frame) {
      const bytes = new Uint8Array(frame);
      const c = channels[bytes[0]];
      if (!closed && c && c.readyState === 'open') c.send(bytes.subarray(1));
    },
    close() {
      pc.close();
      close();
    },
  };
}
