/**
 * What a server needs when every player comes from one loopback address
 * (load tests, the soak, benches and tests): every per-address limit lifted
 * (HTTP requests and sessions per IP, failed authentications and /metrics and /api/health requests per IP, drops
 * and joins per IP, WebSocket frames and bytes per IP, sockets per IP and in total, HTTP connections per IP). Per-player and per-connection limits stay as configured.
 * One copy for every launcher, so they cannot drift apart.
 */
export const LIFTED_LIMITS = Object.freeze({
  HTTP_RATE_LIMIT: '1000000000',
  SESSION_RATE_LIMIT: '1000000000',
  AUTH_FAILURE_LIMIT: '1000000000',
  MONITORING_RATE_LIMIT: '1000000000',
  DROP_RATE_PER_IP: '1000000',
  JOIN_RATE_PER_IP: '1000000',
  WS_MAX_CONNECTIONS_PER_IP: '1000000',
  HTTP_MAX_CONNECTIONS_PER_IP: '1000000',
  WS_MAX_CONNECTIONS: '1000000',
  WS_IP_MESSAGE_RATE: '1000000000',
  WS_IP_BYTE_RATE: '1000000000000'
})
