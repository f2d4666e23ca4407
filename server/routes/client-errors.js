import { STATUS_CODES } from 'node:http'

/**
 * What a client gets for a request that never reaches the routes: Node's
 * HTTP parser refused it, or it did not arrive whole in time. Fastify's own
 * answer has no `code`; these carry one like every other error:
 *   431 E_HEADERS_TOO_LARGE  the header block is larger than Node accepts
 *   408 E_TIMEOUT            the request did not arrive whole within HTTP_REQUEST_TIMEOUT_MS
 *   400 E_BAD_REQUEST        anything else the parser refuses (bad framing, a malformed chunked body)
 * The connection is closed afterwards. Logged once, at debug level: a
 * client that sends garbage must not fill the logs. Fastify's
 * `clientErrorHandler` option: `this` is the fastify instance.
 * @this {import('fastify').FastifyInstance}
 * @param {NodeJS.ErrnoException} error @param {import('node:net').Socket} socket
 */
export function clientErrorHandler (error, socket) {
  if (error.code === 'ECONNRESET' || socket.destroyed) return
  const [status, code, message] = error.code === 'HPE_HEADER_OVERFLOW'
    ? [431, 'E_HEADERS_TOO_LARGE', 'request headers are too large']
    : error.code === 'ERR_HTTP_REQUEST_TIMEOUT'
      ? [408, 'E_TIMEOUT', 'the request did not arrive whole in time']
      : [400, 'E_BAD_REQUEST', `malformed HTTP request (${error.code ?? 'parse error'})`]
  this.log.debug({ code: error.code, remoteAddress: socket.remoteAddress }, 'client error')
  if (socket.writable) {
    const body = JSON.stringify({ code, message })
    socket.write(`HTTP/1.1 ${status} ${STATUS_CODES[status]}\r\nContent-Type: application/json; charset=utf-8\r\nContent-Length: ${Buffer.byteLength(body)}\r\nConnection: close\r\n\r\n${body}`)
  }
  socket.destroy()
}

/**
 * onRequest: an HTTP/1.1 request without a Host header is refused with a
 * code (Node's own check, turned off in app.js, answers with an empty body).
 */
export async function requireHost (request, reply) {
  if (request.raw.httpVersion === '1.1' && !request.headers.host) {
    reply.code(400).send({ code: 'E_BAD_REQUEST', message: 'an HTTP/1.1 request needs a Host header' })
    return reply
  }
}
