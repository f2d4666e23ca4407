/**
 * What package.json declares about installing and running the project,
 * checked against what the other files do: every dependency with an install
 * script is listed in `allowScripts` (npm 11 warns about the others, npm 12
 * skips them), and one Node major, 24, is the one `engines` names, the
 * Docker image runs, CI installs and the README states.
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

  it('names Node 24 as engines, the Docker image, CI and the README do', () => {
    expect(manifest.engines).toEqual({ node: '>=24' })
    expect(read('Dockerfile').match(/^FROM .*$/gm)).toEqual(['FROM node:24-bookworm-slim'])
    expect(read('.ci/run')).toMatch(/^NODE24_VERSION=24\.\d+\.\d+$/m)
    expect(read('.ci/run')).toMatch(/"\$\(node -p 'process\.versions\.node\.split\("\."\)\[0\]'\)" = 24 \] \|\| \{ echo "the suite runs on Node 24/)
    const quickStart = read('README.md').split('## Quick start')[1].split('\n## ')[0]
    expect(quickStart).toMatch(/^Node 24, the current LTS: the version CI runs the whole suite on/m)
    expect(quickStart).toContain('(`node:24-bookworm-slim`)')
    expect(quickStart).toContain('(`>=24`)')
  })
})
