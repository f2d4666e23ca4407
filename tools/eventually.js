/**
 * Polls `check` (sync or async) until it returns a truthy value, which it
 * returns; throws after `timeoutMs`. No vitest import: scripts use the
 * helpers that use it too.
 */
export async function eventually (check, { timeoutMs = 30_000, intervalMs = 20 } = {}) {
  const deadline = Date.now() + timeoutMs
  for (;;) {
    const value = await check()
    if (value) return value
    if (Date.now() > deadline) throw new Error('condition not met in time')
    await new Promise((resolve) => setTimeout(resolve, intervalMs))
  }
}
