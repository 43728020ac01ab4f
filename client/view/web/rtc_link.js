// The page's WebRTC data channels to jetrace-server (docs/PROTOCOL.md,
// "Transport: WebRTC data channel"). RTCPeerConnection exists on the main
// thread only, not in Web Workers: this side holds the connection and the
// two channels, and client_source.js relays their messages to and from the
// worker's socket shim (one frame: a channel byte and one message, as on
// the WebSocket). "unreliable" (unordered, no retransmissions) carries
// channel 0, "reliable" (ordered, reliable) channel 1.

// Opens both channels: resolves with the link, or rejects with the reason
// (the POST /rtc refused, or the channels not open within `timeoutMs`).
export async function openRtcLink(timeoutMs) {
  if (typeof RTCPeerConnection !== 'function') throw new Error('no RTCPeerConnection in this browser');
  const pc = new RTCPeerConnection({ iceServers: [] });
  const channels = [
    pc.createDataChannel('unreliable', { ordered: false, maxRetransmits: 0 }),
    pc.createDataChannel('reliable', { ordered: true }),
  ];
  for (const c of channels) c.binaryType = 'arraybuffer';
  let timer = null;
  try {
    const opened = Promise.all(channels.map((c) => new Promise((resolve, reject) => {
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
    throw e;
  } finally {
    clearTimeout(timer);
  }
  return rtcLink(pc, channels);
}

function rtcLink(pc, channels) {
  const handlers = { frame() {}, close() {} };
  let closed = false;
  const close = () => {
    if (closed) return;
    closed = true;
    handlers.close();
  };
  channels.forEach((c, channel) => {
    c.onmessage = (e) => {
      if (!(e.data instanceof ArrayBuffer)) return;
      const frame = new Uint8Array(e.data.byteLength + 1);
      frame[0] = channel;
      frame.set(new Uint8Array(e.data), 1);
      handlers.frame(frame.buffer);
    };
    c.onclose = close;
  });
  pc.onconnectionstatechange = () => {
    if (pc.connectionState === 'failed' || pc.connectionState === 'closed') close();
  };
  return {
    on(h) { Object.assign(handlers, h); },
    get open() { return !closed; },
    // One frame from the worker: its channel byte picks the data channel.
    send(frame) {
      const bytes = new Uint8Array(frame);
      const c = channels[bytes[0]];
      if (closed || !c || c.readyState !== 'open') return false;
      c.send(bytes.subarray(1));
      return true;
    },
    close() {
      if (!closed) pc.close();
      close();
    },
  };
}
