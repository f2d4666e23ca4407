import path from 'node:path'
import { fileURLToPath } from 'node:url'

const ROOT = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', '..')

/**
 * Where the time of a V8 CPU profile (`node --cpu-prof`) went: self time by
 * function and by area (our engine, our server, each npm package, Node's
 * internals, GC, idle), and inclusive time of the server's own functions.
 * @param {{ nodes: any[], samples: number[], timeDeltas: number[], startTime: number, endTime: number }} profile
 * @param {{ top?: number, from?: number, to?: number }} [options] from/to: µs since the profile started (default: all)
 */
export function summarizeCpuProfile (profile, { top = 25, from = 0, to = Infinity } = {}) {
  const byId = new Map(profile.nodes.map((node) => [node.id, node]))
  const parent = new Map()
  for (const node of profile.nodes) for (const child of node.children ?? []) parent.set(child, node.id)
  const self = new Map()
  let elapsed = 0
  let total = 0
  for (let i = 0; i < profile.samples.length; i++) {
    const delta = profile.timeDeltas[i] ?? 0
    elapsed += delta
    if (elapsed < from || elapsed > to) continue
    self.set(profile.samples[i], (self.get(profile.samples[i]) ?? 0) + delta)
    total += delta
  }

  const functions = new Map()
  const areas = new Map()
  const inclusive = new Map()
  for (const [id, micros] of self) {
    const node = byId.get(id)
    const key = functionKey(node.callFrame)
    const entry = functions.get(key) ?? { name: key, area: areaOf(node.callFrame), micros: 0 }
    entry.micros += micros
    functions.set(key, entry)
    areas.set(entry.area, (areas.get(entry.area) ?? 0) + micros)
    // Inclusive time: credit every distinct function on the stack once.
    const seen = new Set()
    for (let at = id; at !== undefined; at = parent.get(at)) {
      const frameKey = functionKey(byId.get(at).callFrame)
      if (seen.has(frameKey)) continue
      seen.add(frameKey)
      inclusive.set(frameKey, (inclusive.get(frameKey) ?? 0) + micros)
    }
  }
  const share = (micros) => (total > 0 ? micros / total : 0)
  return {
    totalMs: total / 1000,
    areas: [...areas].map(([area, micros]) => ({ area, ms: micros / 1000, share: share(micros) })).sort((a, b) => b.ms - a.ms),
    selfTop: [...functions.values()].sort((a, b) => b.micros - a.micros).slice(0, top)
      .map((f) => ({ name: f.name, area: f.area, ms: f.micros / 1000, share: share(f.micros) })),
    inclusiveTop: [...inclusive].filter(([key]) => key.includes('server/') || key.includes('engine/'))
      .sort((a, b) => b[1] - a[1]).slice(0, top)
      .map(([name, micros]) => ({ name, ms: micros / 1000, share: share(micros) }))
  }
}

/**
 * A profile's busy time split into named parts: each sample goes to the
 * part of the deepest frame on its stack that some part's `match` claims
 * (a socket write under the fan-out is fan-out, a JSON.stringify under the
 * owner's reply is that reply), or to `other`; idle is left out.
 * @param {{ nodes: any[], samples: number[], timeDeltas: number[] }} profile
 * @param {{ name: string, match: (frame: { functionName: string, file: string }) => boolean }[]} parts
 * @param {{ from?: number, to?: number }} [window] µs since the profile started
 * @returns {{ busyMs: number, parts: { name: string, ms: number, share: number }[] }} share of busy time
 */
export function profileParts (profile, parts, { from = 0, to = Infinity } = {}) {
  const byId = new Map(profile.nodes.map((node) => [node.id, node]))
  const parent = new Map()
  for (const node of profile.nodes) for (const child of node.children ?? []) parent.set(child, node.id)
  const partOf = new Map()
  const classify = (id) => {
    if (partOf.has(id)) return partOf.get(id)
    const { functionName, url } = byId.get(id).callFrame
    const frame = { functionName, file: url ? shortUrl(url) : '' }
    let part = parts.find((p) => p.match(frame))?.name
    if (part === undefined) part = parent.has(id) ? classify(parent.get(id)) : 'other'
    partOf.set(id, part)
    return part
  }
  const micros = new Map()
  let elapsed = 0
  let busy = 0
  for (let i = 0; i < profile.samples.length; i++) {
    const delta = profile.timeDeltas[i] ?? 0
    elapsed += delta
    if (elapsed < from || elapsed > to) continue
    const id = profile.samples[i]
    if (byId.get(id).callFrame.functionName === '(idle)') continue
    const part = classify(id)
    micros.set(part, (micros.get(part) ?? 0) + delta)
    busy += delta
  }
  return {
    busyMs: busy / 1000,
    parts: [...parts.map((p) => p.name), 'other'].filter((name, i, all) => all.indexOf(name) === i)
      .map((name) => ({ name, ms: (micros.get(name) ?? 0) / 1000, share: busy > 0 ? (micros.get(name) ?? 0) / busy : 0 }))
  }
}

function functionKey ({ functionName, url, lineNumber }) {
  const name = functionName || '(anonymous)'
  if (!url) return name
  return `${name} ${shortUrl(url)}:${lineNumber + 1}`
}

function shortUrl (url) {
  const file = url.startsWith('file://') ? fileURLToPath(url) : url
  return file.startsWith(ROOT + path.sep) ? path.relative(ROOT, file) : file
}

/** @returns {string} engine, server, npm:<package>, node (internals), or V8's (garbage collector), (idle), (program) */
export function areaOf ({ functionName, url }) {
  if (!url) return functionName.startsWith('(') ? functionName : 'native'
  const file = url.startsWith('file://') ? fileURLToPath(url) : url
  if (file.startsWith('node:')) return 'node'
  const modules = file.lastIndexOf(`node_modules${path.sep}`)
  if (modules >= 0) {
    const rest = file.slice(modules + 'node_modules/'.length).split(path.sep)
    return `npm:${rest[0].startsWith('@') ? `${rest[0]}/${rest[1]}` : rest[0]}`
  }
  const relative = path.relative(ROOT, file)
  if (!relative.startsWith('..')) return relative.split(path.sep)[0]
  return 'other'
}
