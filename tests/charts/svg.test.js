/**
 * charts/svg.js, the one SVG writer behind the `plinko rtp` chart
 * (cli/distribution-chart.js), the load-test report's chart
 * (loadtest/driver/svg-chart.js) and the operator page's charts
 * (client/rtp-chart.js): markup for files, DOM nodes for the page, the
 * same tree for both.
 */
import { describe, it, expect } from 'vitest'
import { execFileSync } from 'node:child_process'
import { mkdtempSync, readFileSync, rmSync } from 'node:fs'
import { tmpdir } from 'node:os'
import { join } from 'node:path'
import { fileURLToPath } from 'node:url'
import { svg, svgMarkup, svgDocument, svgElement, escapeXml, SVG_NAMESPACE } from '../../charts/svg.js'

const ROOT = fileURLToPath(new URL('../../', import.meta.url))

/** Just enough of a DOM to see what svgElement builds. */
const fakeDocument = {
  createElementNS: (namespace, tag) => ({
    namespace,
    tag,
    attributes: [],
    children: [],
    setAttribute (name, value) { this.attributes.push([name, value]) },
    append (...nodes) { this.children.push(...nodes) }
  }),
  createTextNode: (text) => ({ text })
}

describe('the SVG writer', () => {
  const tree = svg('svg', { width: 100, height: 50 },
    svg('rect', { width: 100, height: 50, fill: '#fff', skipped: undefined }),
    [svg('text', { x: 4, y: 20 }, 'RTP < 1 & "fair" ', svg('tspan', { fill: '#555' }, 99, '%')), false, null],
    undefined)

  it('writes a document: the root\'s children one per line, the namespace first, text and attributes escaped', () => {
    expect(svgDocument(tree)).toBe([
      `<svg xmlns="${SVG_NAMESPACE}" width="100" height="50">`,
      '<rect width="100" height="50" fill="#fff"/>',
      '<text x="4" y="20">RTP &lt; 1 &amp; &quot;fair&quot; <tspan fill="#555">99%</tspan></text>',
      '</svg>'
    ].join('\n') + '\n')
    expect(svgMarkup(svg('title', { 'aria-label': 'a "b" <c>' }, 'x'))).toBe('<title aria-label="a &quot;b&quot; &lt;c&gt;">x</title>')
    expect(escapeXml('<&>"')).toBe('&lt;&amp;&gt;&quot;')
  })

  it('builds the same tree as DOM nodes, text as text nodes, never parsed', () => {
    const root = svgElement(tree, fakeDocument)
    expect(root).toMatchObject({ namespace: SVG_NAMESPACE, tag: 'svg', attributes: [['width', '100'], ['height', '50']] })
    expect(root.children.map((c) => c.tag)).toEqual(['rect', 'text'])
    expect(root.children[0].attributes).toEqual([['width', '100'], ['height', '50'], ['fill', '#fff']])
    const [label, tspan] = root.children[1].children
    expect(label).toEqual({ text: 'RTP < 1 & "fair" ' })
    expect(tspan.children).toEqual([{ text: '99' }, { text: '%' }])
  })

  it('draws docs/distribution-16-rows.svg byte for byte as it is committed (scripts/distribution-chart.js)', () => {
    const dir = mkdtempSync(join(tmpdir(), 'plinko-chart-'))
    try {
      const out = join(dir, 'chart.svg')
      execFileSync(process.execPath, [join(ROOT, 'scripts/distribution-chart.js'), '--rows', '16', '--out', out], { cwd: ROOT, timeout: 60_000 })
      expect(readFileSync(out, 'utf8')).toBe(readFileSync(join(ROOT, 'docs/distribution-16-rows.svg'), 'utf8'))
    } finally {
      rmSync(dir, { recursive: true, force: true })
    }
  })

  it('is the only SVG writer: the three charts build on it and write no markup of their own', () => {
    for (const file of ['cli/distribution-chart.js', 'loadtest/driver/svg-chart.js', 'client/rtp-chart.js']) {
      const source = readFileSync(join(ROOT, file), 'utf8')
      expect(source, file).toMatch(/import \{ svg, svg(Document|Element) \} from '(\.\.\/|\.\.\/\.\.\/|\/)charts\/svg\.js'/)
      expect(source, file).not.toMatch(/<\/?(svg|rect|line|text)\b|createElementNS|&amp;/)
    }
  })
})
