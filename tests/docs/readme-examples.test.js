import { describe, it, expect } from 'vitest'
import { execFile } from 'node:child_process'
import fs from 'node:fs'
import path from 'node:path'
import { fileURLToPath } from 'node:url'
import { promisify } from 'node:util'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..')
const run = promisify(execFile)
const PACKAGE = JSON.parse(fs.readFileSync(path.join(ROOT, 'package.json'), 'utf8'))

/**
 * The README's example commands, run as a user would and compared with what
 * the README shows. An example is a fenced block right after an HTML comment
 * starting `<!-- example`; in it, a line `$ npx plinko …` is a command and
 * the lines up to the next `$` are what it prints on stdout. Only `npx
 * plinko` commands are run (arguments split on spaces: no quoting).
 */
export function readmeExamples (markdown) {
  const examples = []
  const block = /<!-- example\b[^>]*-->\s*\n```[a-z]*\n([\s\S]*?)\n```/g
  for (const match of markdown.matchAll(block)) {
    const line = markdown.slice(0, match.index).split('\n').length
    let current = null
    for (const text of match[1].split('\n')) {
      if (text.startsWith('$ ')) {
        current = { line, command: text.slice(2), output: [] }
        examples.push(current)
      } else if (current) {
        current.output.push(text)
      } else {
        throw new Error(`README.md:${line}: an example block must start with a "$ " command line, got ${JSON.stringify(text)}`)
      }
    }
  }
  return examples
}

describe('README examples', () => {
  // The README and the manual it links (docs/*.md).
  const files = ['README.md', ...fs.readdirSync(path.join(ROOT, 'docs')).filter((name) => name.endsWith('.md')).map((name) => `docs/${name}`)]
  const examples = files.flatMap((file) => readmeExamples(fs.readFileSync(path.join(ROOT, file), 'utf8')).map((example) => ({ ...example, file })))

  it('are there to run', () => {
    expect(examples.length).toBeGreaterThanOrEqual(2)
    for (const { command } of examples) expect(command).toMatch(/^npx plinko [^'"\\]+$/)
  })

  it('finds commands and their output, and refuses a block that does not start with one', () => {
    expect(readmeExamples('<!-- example -->\n```console\n$ npx plinko a\none\ntwo\n$ npx plinko b\nthree\n```\n')).toEqual([
      { line: 1, command: 'npx plinko a', output: ['one', 'two'] },
      { line: 1, command: 'npx plinko b', output: ['three'] }
    ])
    expect(() => readmeExamples('<!-- example -->\n```sh\n{"x":1}\n```\n')).toThrow(/must start with a "\$ " command/)
  })

  it.each(examples.map((example) => [example.command, example]))('prints what the README shows: %s', async (command, { file, line, output }) => {
    // What `npx plinko` runs here: the bin package.json declares (run with node directly, which saves npx's second of start-up).
    const [name, ...args] = command.slice('npx '.length).split(/ +/)
    const { stdout } = await run(process.execPath, [path.join(ROOT, PACKAGE.bin[name]), ...args], { cwd: ROOT, encoding: 'utf8', timeout: 30_000 })
    expect(stdout.trimEnd(), `${file}:${line}: ${command}`).toBe(output.join('\n').trimEnd())
  })
})
