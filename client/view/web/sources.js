// Where the page's race comes from. Both kinds hand the page the same
// messages (docs/VIEWER.md, "Messages": a hello, then frames) and take the
// same requests (keys, timeline), so one page draws replays, watched races
// and driven ones:
//   viewerSource: jetrace-view's WebSocket (replays; live races through a
//     native client beside the browser);
//   clientSource (client_source.js): the client library itself, in
//     WebAssembly, connected straight to jetrace-server --web.
// A source calls on({open, close(text), message(text)}) handlers.
export function viewerSource() {
  const socket = new WebSocket('ws://' + location.host + '/ws');
  const handlers = { open() {}, close() {}, message() {} };
  socket.addEventListener('open', () => handlers.open());
  socket.addEventListener('close', (e) => handlers.close('disconnected (' + e.code + ')'));
  socket.addEventListener('message', (e) => handlers.message(typeof e.data === 'string' ? e.data : ''));
  return {
    kind: 'viewer',
    on(h) { Object.assign(handlers, h); },
    send(msg) { if (socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(msg)); },
    sendRaw(text) { socket.send(text); },
    async trackBytes() {
      const response = await fetch('/track.bin');
      if (!response.ok) throw new Error('track.bin: HTTP ' + response.status);
      return response.arrayBuffer();
    },
    stats: () => null,
  };
}
