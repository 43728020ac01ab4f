// Why the client closed, by close code (docs/PROTOCOL.md, "Close codes").
const CLOSE_TEXT = {
  1000: 'left the race', 1001: 'the server stopped', 1002: 'replaced by a newer connection of this player',
  1003: 'the lobby was cancelled (not enough players)',
  2000: 'refused: this page speaks another protocol version', 2001: 'refused: the connect token is not valid',
  2002: 'refused: clock', 2003: 'refused: the race is full', 2004: 'refused: no car to reconnect to',
  2005: 'refused: the server is draining', 2006: 'refused: the server is not allocated to a race yet',
  2007: 'refused: every observer place is taken', 2008: 'refused: too many connections from your address are joining',
  3000: 'left', 3001: 'this page does not know the server\'s track or physics',
  3002: 'no welcome from the server', 3003: 'could not connect to the server, or the connection was lost',
  3004: 'the server\'s track download was bad',
  4000: 'no hello in time', 4001: 'a malformed message', 4002: 'a message out of place',
  4003: 'the page read too slowly (the server\'s send queue overflowed)',
};

export function closeText(code, reason) {
  const text = CLOSE_TEXT[code] || reason || 'closed';
  return text + ' (code ' + code + ')';
}
