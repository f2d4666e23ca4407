import { describe, it, expect } from 'vitest'
import { readdirSync, readFileSync } from 'node:fs'

// The engine may use only + - * /, Math.sqrt, comparisons and integer
// operations in anything that decides an outcome: transcendental functions
// and pow differ between JavaScript engines in their last bits, and
// Math.random, clocks or unordered iteration would make runs differ.
const ENGINE_DIR = new URL('../../engine/', import.meta.url)
const FORBIDDEN = [
  [/Math\.(sin|cos|tan|asin|acos|atan|atan2|sinh|cosh|tanh|asinh|acosh|atanh|pow|hypot|exp|expm1|log|log2|log10|log1p|cbrt|random)\b/, 'inexact or random Math function'],
  [/\*\*/, 'exponent operator'],
  [/\bDate\b|performance\.now|hrtime/, 'clock'],
  [/for\s*\(\s*(const|let|var)\s+\w+\s+in\b/, 'for...in over object keys']
]

function sourceWithoutComments (text) {
  return text.replace(/\/\*[\s\S]*?\*\//g, '').replace(/(^|[^:])\/\/.*$/gm, '$1')
}

describe('engine determinism rules', () => {
  const files = readdirSync(ENGINE_DIR).filter((name) => name.endsWith('.js'))

  it('covers the engine sources', () => {
    expect(files).toContain('world.js')
    expect(files.length).toBeGreaterThan(10)
  })

  for (const name of files) {
    it(`${name} uses only exact, deterministic operations`, () => {
      const code = sourceWithoutComments(readFileSync(new URL(name, ENGINE_DIR), 'utf8'))
      for (const [pattern, what] of FORBIDDEN) {
        const match = code.match(pattern)
        expect(match, `${name}: ${what}: ${match?.[0]}`).toBeNull()
      }
      // Maps and Sets are allowed only where nothing iterates them.
      if (/\bnew (Map|Set)\b/.test(code)) {
        expect(code, `${name} iterates a Map or Set`).not.toMatch(/for\s*\(\s*const\s+\S+\s+of\s+\w+(\.(values|keys|entries)\(\))?\s*\)/)
      }
    })
  }

  it('imports nothing but its own modules and seedrandom', () => {
    for (const name of files) {
      const code = readFileSync(new URL(name, ENGINE_DIR), 'utf8')
      for (const [, spec] of code.matchAll(/from\s+'([^']+)'/g)) {
        expect(spec.startsWith('./') || spec === 'seedrandom', `${name} imports ${spec}`).toBe(true)
      }
    }
  })
})
