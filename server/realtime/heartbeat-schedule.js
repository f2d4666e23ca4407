/**
 * Pings every connection once per heartbeat period (WS_HEARTBEAT_MS), spread
 * over the period's ticks instead of all in one: each connection gets a
 * slot, a tick of the period, round robin as it connects, and is pinged
 * when the clock reaches its slot, so exactly one period apart every time.
 * Pinging all 3,000 connections of a loaded process in one tick wrote 3,000
 * frames in one turn of the event loop (about 70 ms on a 2-core machine)
 * and held the next ticks that long; spread over 1,800 ticks it is two a
 * tick. A burst of connections (a reconnect storm) is spread the same way.
 * Only slots with connections exist (a period of an hour has 216,000
 * ticks; a few thousand connections fill a few thousand of them).
 */
export class HeartbeatSchedule {
  /** @param {number} periodTicks ticks between two pings of one connection (≥ 1) */
  constructor (periodTicks) {
    this.periodTicks = periodTicks
    /** Connections by slot, for the slots that have any. @type {Map<number, Set<{ heartbeat: () => void }>>} */
    this.slots = new Map()
    /** @type {Map<{ heartbeat: () => void }, number>} */
    this.slotOf = new Map()
    this.nextSlot = 0
  }

  /** @param {{ heartbeat: () => void }} connection */
  add (connection) {
    if (this.slotOf.has(connection)) return
    const slot = this.nextSlot
    this.nextSlot = (slot + 1) % this.periodTicks
    let connections = this.slots.get(slot)
    if (!connections) this.slots.set(slot, connections = new Set())
    connections.add(connection)
    this.slotOf.set(connection, slot)
  }

  /** @param {{ heartbeat: () => void }} connection */
  remove (connection) {
    const slot = this.slotOf.get(connection)
    if (slot === undefined) return
    const connections = this.slots.get(slot)
    connections.delete(connection)
    if (connections.size === 0) this.slots.delete(slot)
    this.slotOf.delete(connection)
  }

  /** The clock's tick `tick`: pings the connections whose slot it is. @param {number} tick */
  tick (tick) {
    // A connection that a heartbeat terminates may leave its slot while it is walked: Sets allow that.
    const connections = this.slots.get(tick % this.periodTicks)
    if (connections) for (const connection of connections) connection.heartbeat()
  }
}
