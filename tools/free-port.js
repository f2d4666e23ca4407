import net from 'node:net'

/** A free TCP port on loopback (the OS picks it). */
export function freePort () {
  return new Promise((resolve, reject) => {
    const probe = net.createServer()
    probe.unref()
    probe.once('error', reject)
    probe.listen(0, '127.0.0.1', () => {
      const { port } = probe.address()
      probe.close(() => resolve(port))
    })
  })
}

/**
 * The first of `count` consecutive free loopback ports (npm run cluster
 * takes PORT for its proxy and PORT+1… for its workers).
 * @param {number} count
 */
export async function freePortRun (count) {
  for (let attempt = 0; attempt < 50; attempt++) {
    const base = 20000 + Math.floor(Math.random() * 40000)
    const free = await Promise.all(Array.from({ length: count }, (_, i) => new Promise((resolve) => {
      const probe = net.createServer().once('error', () => resolve(false)).listen(base + i, '127.0.0.1', () => probe.close(() => resolve(true)))
    })))
    if (free.every(Boolean)) return base
  }
  throw new Error(`no run of ${count} free loopback ports`)
}
