/**
 * The one SVG writer of the project's charts: a chart is built as a small
 * tree of plain objects, then written either as markup (a file: the `plinko
 * rtp` chart, the load-test report, docs/) or as DOM nodes (the operator
 * page, without markup strings). Runs in Node and, served at /charts/, in
 * the browser; it imports nothing.
 *
 *   const chart = svg('svg', { width: 100, height: 50 },
 *     svg('rect', { width: 100, height: 50, fill: '#fff' }),
 *     svg('text', { x: 4, y: 20 }, 'RTP ', svg('tspan', { fill: '#555' }, '99%')))
 *   svgDocument(chart)            // '<svg width="100" height="50">\n<rect …/>\n<text …>RTP <tspan …>99%</tspan></text>\n</svg>\n'
 *   svgElement(chart, document)   // an SVGSVGElement
 */

export const SVG_NAMESPACE = 'http://www.w3.org/2000/svg'

/**
 * @typedef {{ tag: string, attributes: Record<string, string | number>, children: (SvgNode | string)[] }} SvgNode
 * A string child is text (escaped when written as markup).
 */

/**
 * @param {string} tag
 * @param {Record<string, string | number | undefined | null>} [attributes] in the order they are written; undefined and null are left out
 * @param {...(SvgNode | string | number | false | null | undefined | any[])} children arrays are flattened; false, null and undefined are left out
 * @returns {SvgNode}
 */
export function svg (tag, attributes = {}, ...children) {
  const kept = {}
  for (const [name, value] of Object.entries(attributes)) if (value !== undefined && value !== null) kept[name] = value
  const nodes = []
  for (const child of children.flat(Infinity)) {
    if (child === false || child === null || child === undefined) continue
    nodes.push(typeof child === 'object' ? child : String(child))
  }
  return { tag, attributes: kept, children: nodes }
}

/** @param {unknown} text @returns {string} text safe inside an element or an attribute value */
export function escapeXml (text) {
  return String(text).replace(/[<>&"]/g, (c) => ({ '<': '&lt;', '>': '&gt;', '&': '&amp;', '"': '&quot;' })[c])
}

/**
 * One node as markup, on one line: `<tag a="1"/>` when it has no children.
 * @param {SvgNode | string} node @returns {string}
 */
export function svgMarkup (node) {
  if (typeof node === 'string') return escapeXml(node)
  if (node.children.length === 0) return `<${node.tag}${attributeMarkup(node.attributes)}/>`
  return `<${node.tag}${attributeMarkup(node.attributes)}>${node.children.map(svgMarkup).join('')}</${node.tag}>`
}

function attributeMarkup (attributes) {
  return Object.entries(attributes).map(([name, value]) => ` ${name}="${escapeXml(value)}"`).join('')
}

/**
 * A whole SVG file: the root's opening tag, each of its children on a line
 * of its own, the closing tag, a final newline. The root gets the SVG
 * namespace first unless it names one.
 * @param {SvgNode} root @returns {string}
 */
export function svgDocument (root) {
  const open = `<${root.tag}${attributeMarkup({ xmlns: SVG_NAMESPACE, ...root.attributes })}>`
  return [open, ...root.children.map(svgMarkup), `</${root.tag}>`].join('\n') + '\n'
}

/**
 * The tree as DOM nodes of `document` (createElementNS, setAttribute,
 * createTextNode: text is never parsed as markup).
 * @param {SvgNode | string} node @param {Document} [document]
 * @returns {SVGElement | Text}
 */
export function svgElement (node, document = globalThis.document) {
  if (typeof node === 'string') return document.createTextNode(node)
  const element = document.createElementNS(SVG_NAMESPACE, node.tag)
  for (const [name, value] of Object.entries(node.attributes)) element.setAttribute(name, String(value))
  for (const child of node.children) element.append(svgElement(child, document))
  return element
}
