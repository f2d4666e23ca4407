import fs from 'node:fs'
import path from 'node:path'

/**
 * The project's own JavaScript files (no node_modules, no generated
 * results), read once: what the structure tests look at.
 * @param {string} root
 * @returns {{ file: string, text: string }[]} file: relative, '/'-separated
 */
export function sourceFiles (root) {
  const skip = new Set(['node_modules', '.git', 'data', 'coverage', 'results', 'bin', '.tmp'])
  const files = []
  const walk = (dir) => {
    for (const entry of fs.readdirSync(path.join(root, dir), { withFileTypes: true })) {
      const relative = dir ? `${dir}/${entry.name}` : entry.name
      if (entry.isDirectory()) {
        if (!skip.has(entry.name) || relative === 'bin') walk(relative)
      } else if (/\.(m?js)$/.test(entry.name)) {
        files.push({ file: relative, text: fs.readFileSync(path.join(root, relative), 'utf8') })
      }
    }
  }
  walk('')
  return files.sort((a, b) => (a.file < b.file ? -1 : 1))
}

/**
 * The relative and bare module specifiers a file imports (static, dynamic
 * and re-exports), resolved against the file: 'engine/board.js', or the
 * bare name ('seedrandom', 'node:fs'); a page's '/engine/x.js' is 'engine/x.js'.
 * @param {string} file @param {string} text
 */
export function importsOf (file, text) {
  const specifiers = new Set()
  const code = text.replace(/\/\*[\s\S]*?\*\//g, '').replace(/^\s*\/\/.*$/gm, '')
  for (const match of code.matchAll(/(?:^|[\s;])(?:import|export)\s[^'"`;]*?from\s*['"]([^'"]+)['"]|(?:^|[\s;(])import\s*\(\s*['"]([^'"]+)['"]\s*\)|^\s*import\s*['"]([^'"]+)['"]/gm)) {
    const specifier = match[1] ?? match[2] ?? match[3]
    if (specifier.startsWith('.')) specifiers.add(path.posix.normalize(path.posix.join(path.posix.dirname(file), specifier)))
    else if (specifier.startsWith('/')) specifiers.add(specifier.slice(1))
    else specifiers.add(specifier)
  }
  return [...specifiers]
}

/**
 * Functions longer than `limit` lines, found by the code's layout (standard
 * style: a function's closing brace sits at its opening line's indentation).
 * @param {string} text @param {number} limit
 * @returns {{ name: string, line: number, lines: number }[]}
 */
export function longFunctions (text, limit) {
  const lines = text.split('\n')
  const start = /^(\s*)(?:export\s+)?(?:default\s+)?(?:async\s+)?(?:function\s*\*?\s*([\w$]*)\s*\(|(?:static\s+)?(?:get\s+|set\s+)?([\w$]+)\s*\([^)]*\)\s*\{\s*$|(?:const|let)\s+([\w$]+)\s*=\s*(?:async\s+)?(?:function\b|\([^)]*\)\s*=>\s*\{|[\w$]+\s*=>\s*\{))/
  const found = []
  for (let i = 0; i < lines.length; i++) {
    const match = start.exec(lines[i])
    if (!match || !lines[i].trimEnd().endsWith('{')) continue
    const name = match[2] || match[3] || match[4] || '(anonymous)'
    if (['if', 'for', 'while', 'switch', 'catch', 'with'].includes(name)) continue
    const close = new RegExp(`^${match[1]}\\}`)
    let end = i + 1
    while (end < lines.length && !close.test(lines[end])) end++
    const length = end - i + 1
    if (end < lines.length && length > limit) found.push({ name, line: i + 1, lines: length })
  }
  return found
}
