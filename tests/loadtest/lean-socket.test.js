import { describe, it, expect, afterEach } from 'vitest'
import { once } from 'node:events'
import { WebSocketServer } from 'ws'
import { LeanSocket, ServerFrameParser, encodeClientFrame, acceptKey, CLOSE_PROTOCOL_ERROR, CLOSE_TOO_BIG } from '../../loadtest/lean/lean-socket.js'

/** A server frame (unmasked) of `payload`. */
function serverFrame (opcode, payload, fin = true) {
  const length = payload.length
  const head = length < 126 ? Buffer.from([(fin ? 0x80 : 0) | opcode, length]) : length < 65536 ? Buffer.from([(fin ? 0x80 : 0) | opcode, 126, length >> 8, length & 0xff]) : (() => {
    const b = Buffer.alloc(10)
    b[0] = (fin ? 0x80 : 0) | opcode
    b[1] = 127
    b.writeUInt32BE(length, 6)
    return b
  })()
  return Buffer.concat([head, payload])
}

function collect () {
  const frames = []
  const violations = []
  const parser = new ServerFrameParser((fin, opcode, buffer, start, end) => frames.push({ fin, opcode, data: Buffer.from(buffer.subarray(start, end)) }), (code, reason) => violations.push({ code, reason }), 100_000)
  return { parser, frames, violations }
}

describe('ServerFrameParser', () => {
  it('parses frames of every length encoding, whatever the chunking', () => {
    const payloads = [Buffer.alloc(0), Buffer.alloc(125, 1), Buffer.alloc(126, 2), Buffer.alloc(70_000, 3)]
    const stream = Buffer.concat(payloads.map((p, i) => serverFrame(i % 2 ? 1 : 2, p)))
    for (const chunkSize of [1, 3, 7, 190, 65536, stream.length]) {
      const { parser, frames, violations } = collect()
      // A reused read buffer, as with net's onread: the parser must copy what it keeps.
      const scratch = Buffer.alloc(chunkSize)
      for (let at = 0; at < stream.length; at += chunkSize) {
        const n = stream.copy(scratch, 0, at, Math.min(stream.length, at + chunkSize))
        parser.push(scratch, n)
        scratch.fill(0xee)
      }
      expect(violations).toEqual([])
      expect(frames.map((f) => f.data.length)).toEqual([0, 125, 126, 70_000])
      expect(frames.map((f) => f.opcode)).toEqual([2, 1, 2, 1])
      expect(frames.every((f, i) => f.data.equals(payloads[i]))).toBe(true)
    }
  })

  it('refuses masked server frames, reserved bits, bad control frames and oversize frames', () => {
    const cases = [
      [Buffer.from([0x82, 0x80 | 1, 0, 0, 0, 0, 9]), CLOSE_PROTOCOL_ERROR],
      [Buffer.from([0xc2, 0]), CLOSE_PROTOCOL_ERROR],
      [Buffer.from([0x09, 0]), CLOSE_PROTOCOL_ERROR],
      [serverFrame(9, Buffer.alloc(126)), CLOSE_PROTOCOL_ERROR],
      [Buffer.from([0x83, 0]), CLOSE_PROTOCOL_ERROR],
      [serverFrame(2, Buffer.alloc(100_001)), CLOSE_TOO_BIG]
    ]
    for (const [bytes, code] of cases) {
      const { parser, frames, violations } = collect()
      parser.push(Buffer.concat([bytes, serverFrame(2, Buffer.from('after'))]))
      expect(violations.map((v) => v.code)).toEqual([code])
      expect(frames).toEqual([])
    }
  })
})

describe('encodeClientFrame', () => {
  it('masks the payload with the key, RFC 6455 §5.3', () => {
    const frame = encodeClientFrame(1, Buffer.from('Hello'), Buffer.from([0x37, 0xfa, 0x21, 0x3d]))
    // The RFC's own example of a masked "Hello".
    expect([...frame]).toEqual([0x81, 0x85, 0x37, 0xfa, 0x21, 0x3d, 0x7f, 0x9f, 0x4d, 0x51, 0x58])
  })

  it('computes the handshake accept key of RFC 6455 §1.3', () => {
    expect(acceptKey('dGhlIHNhbXBsZSBub25jZQ==')).toBe('s3pPLMBiTxaQ9kYGzzhZRbK+xOo=')
  })
})

describe('LeanSocket against a ws server', () => {
  let server
  afterEach(async () => {
    for (const client of server?.clients ?? []) client.terminate()
    await new Promise((resolve) => server ? server.close(resolve) : resolve())
    server = null
  })

  async function listen (onConnection) {
    server = new WebSocketServer({ host: '127.0.0.1', port: 0, perMessageDeflate: false })
    server.on('connection', onConnection)
    await once(server, 'listening')
    return server.address().port
  }

  function connect (port, path = '/') {
    const seen = { text: [], binary: [], closes: [], errors: [], opened: false }
    let resolveClosed
    seen.closed = new Promise((resolve) => { resolveClosed = resolve })
    const socket = new LeanSocket({ host: '127.0.0.1', port, path }, {
      onOpen: () => { seen.opened = true },
      onText: (text) => seen.text.push(text),
      onBinary: (buffer, start, end) => seen.binary.push(Buffer.from(buffer.subarray(start, end))),
      onClose: (code, reason) => { seen.closes.push({ code, reason }); resolveClosed() },
      onError: (error) => seen.errors.push(error.message)
    })
    return { socket, seen }
  }

  it('exchanges text and binary messages, reassembles fragments, answers pings and closes cleanly', async () => {
    const serverSide = { messages: [], pongs: [], closeCode: null }
    const port = await listen((ws, request) => {
      serverSide.path = request.url
      ws.on('message', (data, isBinary) => {
        serverSide.messages.push(isBinary ? ['binary', data.length] : ['text', data.toString()])
        ws.send('{"type":"welcome"}')
        ws.send(Buffer.from([2, 0, 0, 0, 0, 1, 7, 0, 0, 0]), { binary: true })
        ws.send('frag', { fin: false })
        ws.send('mented', { fin: true })
        ws.ping('are you there')
      })
      ws.on('pong', (data) => serverSide.pongs.push(data.toString()))
      ws.on('close', (code) => { serverSide.closeCode = code })
    })
    const { socket, seen } = connect(port, '/ws?token=abc')
    await new Promise((resolve) => { const timer = setInterval(() => { if (seen.opened) { clearInterval(timer); resolve() } }, 5) })
    socket.sendText('{"type":"join","room":"r"}')
    await new Promise((resolve) => { const timer = setInterval(() => { if (serverSide.pongs.length > 0) { clearInterval(timer); resolve() } }, 5) })
    socket.close(1000)
    await seen.closed
    expect(serverSide.path).toBe('/ws?token=abc')
    expect(serverSide.messages).toEqual([['text', '{"type":"join","room":"r"}']])
    expect(seen.text).toEqual(['{"type":"welcome"}', 'fragmented'])
    expect(seen.binary.map((b) => [...b])).toEqual([[2, 0, 0, 0, 0, 1, 7, 0, 0, 0]])
    expect(serverSide.pongs).toEqual(['are you there'])
    expect(seen.closes).toEqual([{ code: 1000, reason: '' }])
    expect(seen.errors).toEqual([])
    await new Promise((resolve) => { const timer = setInterval(() => { if (serverSide.closeCode !== null) { clearInterval(timer); resolve() } }, 5) })
    expect(serverSide.closeCode).toBe(1000)
  })

  it('reports the server closing with its code and reason', async () => {
    const port = await listen((ws) => ws.close(1013, 'E_SLOW_CONSUMER'))
    const { seen } = connect(port)
    await seen.closed
    expect(seen.closes).toEqual([{ code: 1013, reason: 'E_SLOW_CONSUMER' }])
  })

  it('reports a refused upgrade with its HTTP status, then a 1006 close', async () => {
    const port = await listen(() => {})
    server.options.verifyClient = () => false
    const { seen } = connect(port)
    await seen.closed
    expect(seen.errors).toEqual(['handshake answered HTTP/1.1 401 Unauthorized'])
    expect(seen.closes.map((c) => c.code)).toEqual([1006])
  })
})
