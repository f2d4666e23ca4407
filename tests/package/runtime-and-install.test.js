/**
 * What package.json declares about installing and running the project,
 * checked against what the other files do: every dependency with an install
 * script is listed in `allowScripts` (npm 11 warns about the others, npm 12
 * skips them), nothing is compiled at install, and one Node major, 26, is
 * the one the Docker image runs, CI installs and the README states
 * (`engines` also allows 24).
 */
import { describe, it, expect } from 'vitest'
import { readFileSync } from 'node:fs'

const read = (file) => readFileSync(new URL(`../../${file}`, import.meta.url), 'utf8')
const manifest = JSON.parse(read('package.json'))
const lock = JSON.parse(read('package-lock.json'))

describe('package.json', () => {
  it('lists exactly the dependencies with install scripts in allowScripts, each allowed', () => {
    const withScripts = new Set()
    for (const [where, entry] of Object.entries(lock.packages)) {
      if (where !== '' && entry.hasInstallScript) withScripts.add(where.slice(where.lastIndexOf('node_modules/') + 'node_modules/'.length))
    }
    expect([...withScripts].sort()).toEqual(['bun', 'esbuild'])
    expect(manifest.allowScripts).toEqual(Object.fromEntries([...withScripts].sort().map((name) => [name, true])))
  })

  it('names Node 26 where engines, the Docker image, CI and the README do; engines also allows 24', () => {
    expect(manifest.engines).toEqual({ node: '>=24' })
    expect(read('Dockerfile').match(/^FROM .*$/gm)).toEqual(['FROM node:26-bookworm-slim'])
    expect(read('.ci/run')).toMatch(/^NODE26_VERSION=26\.\d+\.\d+$/m)
    expect(read('.ci/run')).toMatch(/"\$\(node -p 'process\.versions\.node\.split\("\."\)\[0\]'\)" = 26 \] \|\| \{ echo "the suite runs on Node 26/)
    const quickStart = read('README.md').split('## Quick start')[1].split('\n## ')[0]
    expect(quickStart).toMatch(/^Node 26 \(the active LTS\) or 24/m)
    expect(quickStart).toContain('(`node:26-bookworm-slim`)')
  })

  it('builds nothing from source: no native addon, no headers to fetch', () => {
    const addons = Object.entries(lock.packages).filter(([, entry]) => entry.dependencies?.['node-gyp-build'] || entry.dependencies?.bindings || entry.dependencies?.['prebuild-install'])
    expect(addons.map(([where]) => where)).toEqual([])
    expect(read('.ci/run')).not.toMatch(/nodedir|headers/i)
  })
})
