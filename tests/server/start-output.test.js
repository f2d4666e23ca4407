/**
 * What the server prints when it starts (server/server.js): a banner and
 * pretty logs for a person at a terminal, JSON lines for a machine
 * (log-format.js chooses; start-banner.js writes the banner). A real
 * terminal is hard to spawn, so the choice is checked as a function of
 * (isTTY, LOG_FORMAT, pino-pretty installed), and real processes are
 * checked piped: JSON lines by default, the human output with LOG_FORMAT=pretty.
 */
import { describe, it, expect } from 'vitest'
import { existsSync } from 'node:fs'
import { startServerProcess } from '../../tools/server-process.js'
import { loadConfig } from '../../server/config.js'
import { LOG_FORMATS, logOutput, outputMode, prettyTarget } from '../../server/log-format.js'
import { hidePassword, listenUrls, startBanner } from '../../server/start-banner.js'
import { ENGINE_VERSION } from '../../engine/index.js'

const TOKEN = 'a-configured-operator-token-0123'

describe('output mode', () => {
  it('is pretty with a banner only for a terminal (or LOG_FORMAT=pretty), JSON lines otherwise', () => {
    const table = []
    for (const logFormat of LOG_FORMATS) {
      for (const isTTY of [true, false]) {
        for (const prettyAvailable of [true, false]) table.push([logFormat, isTTY, prettyAvailable, outputMode({ isTTY, logFormat, prettyAvailable })])
      }
    }
    expect(table).toEqual([
      ['auto', true, true, { logs: 'pretty', banner: true }],
      // A production install on a terminal: the banner, JSON logs, and no complaint.
      ['auto', true, false, { logs: 'json', banner: true }],
      ['auto', false, true, { logs: 'json', banner: false }],
      ['auto', false, false, { logs: 'json', banner: false }],
      ['json', true, true, { logs: 'json', banner: false }],
      ['json', true, false, { logs: 'json', banner: false }],
      ['json', false, true, { logs: 'json', banner: false }],
      ['json', false, false, { logs: 'json', banner: false }],
      ['pretty', true, true, { logs: 'pretty', banner: true }],
      ['pretty', true, false, { logs: 'json', banner: true, notice: expect.stringMatching(/^LOG_FORMAT=pretty, but pino-pretty .* not installed: logging JSON lines$/) }],
      ['pretty', false, true, { logs: 'pretty', banner: true }],
      ['pretty', false, false, { logs: 'json', banner: true, notice: expect.stringContaining('pino-pretty') }]
    ])
    // isTTY is process.stdout.isTTY: undefined when piped.
    expect(outputMode({ isTTY: undefined, logFormat: 'auto', prettyAvailable: true })).toEqual({ logs: 'json', banner: false })
  })

  it('uses pino-pretty (installed here as a development dependency) only for pretty logs, and writes JSON lines synchronously', () => {
    const target = prettyTarget()
    expect(target).toMatch(/node_modules[/\\]pino-pretty[/\\]/)
    expect(existsSync(target)).toBe(true)
    expect(logOutput('pretty', { target, colorize: true })).toMatchObject({ transport: { target, options: { colorize: true } } })
    // JSON lines go to stdout synchronously: nothing is left in a buffer when the process exits.
    for (const output of [logOutput('json', { target }), logOutput('pretty', { target: null })]) {
      expect(Object.keys(output)).toEqual(['stream'])
      expect(output.stream).toMatchObject({ fd: 1, sync: true })
    }
  })

  it('reads LOG_FORMAT from the environment: auto by default, one of auto, json, pretty', () => {
    expect(loadConfig({}).logFormat).toBe('auto')
    expect(loadConfig({ LOG_FORMAT: 'json' }).logFormat).toBe('json')
    expect(() => loadConfig({ LOG_FORMAT: 'text' })).toThrow('LOG_FORMAT="text": must be one of auto, json, pretty')
  })
})

describe('start-up banner', () => {
  const addresses = [{ address: '127.0.0.1', family: 'IPv4', port: 8080 }]

  it('names the URL, the SQLite file, one process alone, and the generated operator token', () => {
    const config = loadConfig({ DATABASE_URL: 'sqlite:/srv/plinko/ledger.sqlite' })
    const banner = startBanner(config, { urls: ['http://localhost:8080', 'http://10.1.2.3:8080'], logs: 'pretty', node: 'v24.21.0' })
    const lines = banner.split('\n')
    expect(lines[0]).toBe(`Plinko Arena 0.1.0 (engine ${ENGINE_VERSION}, Node v24.21.0)`)
    expect(lines).toContain('  play      http://localhost:8080/')
    expect(lines).toContain('  also      http://10.1.2.3:8080/')
    expect(lines).toContain('  audit     http://localhost:8080/audit (operators)   API: http://localhost:8080/docs')
    expect(lines).toContain('  ledger    SQLite /srv/plinko/ledger.sqlite')
    expect(lines).toContain('  runs      one process alone: every room, nonce and drop id here')
    expect(lines).toContain(`  operator  OPERATOR_TOKEN was not set; generated for this run: ${config.operatorToken}`)
    expect(lines).toContain('            (set OPERATOR_TOKEN, 32 random bytes in hex, to keep one across restarts)')
    expect(lines).toContain('  logs      pretty, below (LOG_FORMAT=json for JSON lines)')
    expect(banner.endsWith('\n\n')).toBe(true)
    expect(lines.length).toBeLessThanOrEqual(14)
  })

  it('hides a configured token and every password, and says when it runs clustered', () => {
    const config = loadConfig({
      DATABASE_URL: 'postgres://plinko:db-secret@db:5432/plinko',
      REDIS_URL: 'redis://:redis-secret@cache:6379/0',
      OPERATOR_TOKEN: TOKEN,
      PUBLIC_URL: 'http://lb:8080/n/server1'
    })
    const banner = startBanner(config, { urls: listenUrls(addresses), logs: 'json' })
    for (const secret of ['db-secret', 'redis-secret', TOKEN]) expect(banner).not.toContain(secret)
    expect(banner).toContain('  ledger    PostgreSQL postgres://plinko:***@db:5432/plinko\n')
    expect(banner).toContain('  runs      clustered: rooms leased through Redis redis://:***@cache:6379/0; this process is http://lb:8080/n/server1\n')
    expect(banner).toContain('  operator  OPERATOR_TOKEN from the environment (not shown)\n')
    expect(banner).toContain('  logs      JSON lines, below (pretty ones need the dev dependency pino-pretty)\n')
    expect(banner).toContain('  play      http://127.0.0.1:8080/\n')
    expect(banner).not.toContain('  also')
    expect(startBanner(loadConfig({ DATABASE_URL: 'sqlite::memory:' }), { urls: [], logs: 'json' })).toContain('  ledger    SQLite in memory (gone when the process exits)\n')
    expect(hidePassword('postgres://u@h/d')).toBe('postgres://u@h/d')
  })

  it('turns a wildcard address into localhost and this machine\'s external addresses', () => {
    const interfaces = {
      lo: [{ address: '127.0.0.1', family: 'IPv4', internal: true }, { address: '::1', family: 'IPv6', internal: true }],
      eth0: [{ address: '10.1.2.3', family: 'IPv4', internal: false }, { address: 'fe80::1', family: 'IPv6', internal: false }, { address: '2001:db8::5', family: 'IPv6', internal: false }]
    }
    expect(listenUrls([{ address: '0.0.0.0', family: 'IPv4', port: 8080 }], interfaces)).toEqual(['http://localhost:8080', 'http://10.1.2.3:8080'])
    expect(listenUrls([{ address: '::', family: 'IPv6', port: 80 }], interfaces)).toEqual(['http://localhost:80', 'http://10.1.2.3:80', 'http://[2001:db8::5]:80'])
    expect(listenUrls([{ address: '::1', family: 'IPv6', port: 9 }, { address: '127.0.0.1', family: 'IPv4', port: 9 }], interfaces)).toEqual(['http://[::1]:9', 'http://127.0.0.1:9'])
  })
})

/**
 * A server process on an in-memory ledger, stopped with SIGTERM once it
 * listens: its exit, and everything it printed (read once its pipes have
 * closed: 'exit' can come before the last chunk is read).
 */
async function runOnce (env) {
  const proc = startServerProcess('sqlite::memory:', { OPERATOR_TOKEN: '', CLIENT_DIR: '/nonexistent/plinko-client', ...env })
  const pipesClosed = new Promise((resolve) => proc.child.once('close', resolve))
  await proc.port
  proc.child.kill('SIGTERM')
  const exit = await proc.exited
  await pipesClosed
  return { exit, output: proc.output() }
}

describe('a server process, piped', () => {
  it('prints JSON lines only, the generated operator token in one of them, and no banner', async () => {
    const { exit, output } = await runOnce({ LOG_FORMAT: 'auto' })
    expect(exit).toEqual({ code: 0, signal: null })
    const lines = output.trimEnd().split('\n')
    const records = lines.map((line) => JSON.parse(line))
    expect(records.length).toBeGreaterThanOrEqual(4)
    for (const record of records) expect(record).toMatchObject({ level: expect.any(Number), time: expect.any(Number), msg: expect.any(String) })
    const token = records.find((record) => record.operatorToken)
    expect(token.operatorToken).toMatch(/^[0-9a-f]{64}$/)
    expect(token.msg).toMatch(/^OPERATOR_TOKEN not set/)
    expect(output).not.toContain('Plinko Arena')
    expect(records.at(-1)).toMatchObject({ msg: 'shut down: 0 drops in flight settled, 0 sockets closed; exit code 0', exitCode: 0 })
  })

  it('prints the banner and pretty logs with LOG_FORMAT=pretty, down to the last line at exit', async () => {
    const { exit, output } = await runOnce({ LOG_FORMAT: 'pretty' })
    expect(exit).toEqual({ code: 0, signal: null })
    const port = /listening at http:\/\/127\.0\.0\.1:(\d+)/.exec(output)[1]
    expect(output.startsWith(`Plinko Arena 0.1.0 (engine ${ENGINE_VERSION}, Node ${process.version})\n  play      http://127.0.0.1:${port}/\n`)).toBe(true)
    expect(output).toContain('  ledger    SQLite in memory (gone when the process exits)\n')
    const token = /generated for this run: ([0-9a-f]{64})\n/.exec(output)[1]
    // The banner shows the token; the logs do not repeat it.
    expect(output.split(token)).toHaveLength(2)
    const logLines = output.slice(output.indexOf('\n\n') + 2).trimEnd().split('\n')
    expect(logLines.length).toBeGreaterThanOrEqual(3)
    for (const line of logLines) {
      expect(line).toMatch(/^\[\d\d:\d\d:\d\d\.\d{3}\] (INFO|WARN): /)
      expect(() => JSON.parse(line)).toThrow()
    }
    // No colours when piped; the transport's worker is flushed before the process exits.
    expect(output).not.toContain('\u001b[')
    expect(logLines.at(-1)).toMatch(/^\[[\d:.]+\] INFO: shut down: 0 drops in flight settled, 0 sockets closed; exit code 0 \{.*"exitCode":0/)
  })

  it('stops gracefully, last line and all, on a SIGTERM that comes while it is still starting', async () => {
    // The first line it prints (the generated token, before it listens) is the moment to send it.
    for (let run = 0; run < 3; run++) {
      const proc = startServerProcess('sqlite::memory:', { OPERATOR_TOKEN: '', CLIENT_DIR: '/nonexistent/plinko-client', LOG_FORMAT: 'json' })
      const pipesClosed = new Promise((resolve) => proc.child.once('close', resolve))
      proc.port.catch(() => {})
      await new Promise((resolve) => proc.child.stdout.once('data', resolve))
      proc.child.kill('SIGTERM')
      const exit = await proc.exited
      await pipesClosed
      const records = proc.output().trimEnd().split('\n').map((line) => JSON.parse(line))
      expect(exit, proc.output()).toEqual({ code: 0, signal: null })
      expect(records.at(-1)).toMatchObject({ msg: 'shut down: 0 drops in flight settled, 0 sockets closed; exit code 0', signal: 'SIGTERM', exitCode: 0 })
    }
  })
})
