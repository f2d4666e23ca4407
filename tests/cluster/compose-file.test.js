import { describe, it, expect } from 'vitest'
import { execFileSync } from 'node:child_process'
import fs from 'node:fs'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import YAML from 'yaml'
import { loadConfig } from '../../server/config.js'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')

/**
 * Docker cannot run here (and `docker compose` is not installed), so the
 * compose file is checked as data: parsed as YAML (the `yaml` package, with
 * the anchors and `<<` merge keys resolved as compose does), its
 * ${VAR:-default}s substituted, and every replica's environment run through loadConfig.
 */
function parseYaml (file) {
  return YAML.parse(fs.readFileSync(file, 'utf8'), { merge: true })
}

const substitute = (value) => String(value).replace(/\$\{(\w+):-([^}]*)\}/g, (_, name, fallback) => fallback)

const compose = parseYaml(path.join(ROOT, 'docker-compose.yml'))
const nginx = fs.readFileSync(path.join(ROOT, 'deploy/nginx.conf'), 'utf8')

describe('docker-compose.yml', () => {
  const services = compose.services ?? {}
  const replicas = Object.entries(services).filter(([, s]) => s.build === '.')

  it('has PostgreSQL, Redis, two or more server replicas, a load balancer and a k6 profile', () => {
    expect(services.postgres.image).toMatch(/^postgres:/)
    expect(services.redis.image).toMatch(/^redis:/)
    expect(replicas.length).toBeGreaterThanOrEqual(2)
    expect(services.lb.ports).toContain('8080:8080')
    expect(services.lb.volumes).toContain('./deploy/nginx.conf:/etc/nginx/nginx.conf:ro')
    expect(services.k6.profiles).toEqual(['loadtest'])
    expect(services.k6.volumes[0]).toMatch(/^\.\/loadtest:/)
    expect(fs.existsSync(path.join(ROOT, 'loadtest', services.k6.command.at(-1).replace('/scripts/', '')))).toBe(true)
  })

  it('gives every replica a valid clustered configuration with its own public URL routed by nginx', () => {
    const urls = new Set()
    for (const [name, service] of replicas) {
      const env = Object.fromEntries(Object.entries(service.environment).map(([k, v]) => [k, substitute(v)]))
      const config = loadConfig(env)
      expect(config.redisUrl).toBe('redis://redis:6379')
      expect(config.database.kind).toBe('postgres')
      expect(new URL(config.database.url).hostname).toBe('postgres')
      expect(config.publicUrl).toBe(`http://localhost:8080/n/${name}`)
      urls.add(config.publicUrl)
      expect(service.depends_on.postgres.condition).toBe('service_healthy')
      expect(service.depends_on.redis.condition).toBe('service_healthy')
      // nginx: the replica is in the upstream and has its own prefix route.
      expect(nginx).toContain(`server ${name}:8080`)
      expect(nginx).toContain(`location /n/${name}/ { proxy_pass http://${name}:8080/; }`)
    }
    expect(urls.size).toBe(replicas.length)
  })

  it('keeps WebSockets working through nginx', () => {
    expect(nginx).toMatch(/proxy_http_version 1\.1;/)
    expect(nginx).toMatch(/proxy_set_header Upgrade \$http_upgrade;/)
    expect(nginx).toMatch(/proxy_set_header Connection \$connection_upgrade;/)
    expect(nginx).toMatch(/proxy_read_timeout \d+s;/)
  })

  it('builds the server from a Dockerfile that copies what server.js imports', () => {
    const dockerfile = fs.readFileSync(path.join(ROOT, 'Dockerfile'), 'utf8')
    for (const [, source] of dockerfile.matchAll(/^COPY (\S+) /gm)) expect(fs.existsSync(path.join(ROOT, source)), source).toBe(true)
    expect(dockerfile).toMatch(/CMD \["node", "server\/server\.js"\]/)
    // Every top-level folder server/ imports from is in the image (engine/ and protocol/ beside server/ itself).
    const imports = execFileSync('grep', ['-rhoE', "from '(\\.\\./)+[a-z-]+/", path.join(ROOT, 'server')], { encoding: 'utf8' })
    const top = new Set([...imports.matchAll(/\.\.\/([a-z-]+)\//g)].map((m) => m[1]).filter((dir) => fs.existsSync(path.join(ROOT, dir))))
    expect([...top].sort()).toEqual(expect.arrayContaining(['engine', 'protocol']))
    for (const dir of top) expect(dockerfile, dir).toContain(`COPY ${dir} ./${dir}`)
  })
})
