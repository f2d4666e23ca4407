import { registerHooks } from 'node:module'

/**
 * `node --import ./bench/better-sqlite3-hooks.js …`: every `node:sqlite` the
 * process imports (its worker threads included, which inherit the flag) is
 * bench/better-sqlite3-shim.js instead, i.e. better-sqlite3. Only
 * bench/sqlite-drivers.js uses it, to measure the store on both drivers.
 */
const shim = new URL('./better-sqlite3-shim.js', import.meta.url).href
registerHooks({
  resolve (specifier, context, nextResolve) {
    if (specifier === 'node:sqlite') return { url: shim, shortCircuit: true }
    return nextResolve(specifier, context)
  }
})
