import { Counter, Gauge, Histogram, Registry, collectDefaultMetrics } from 'prom-client'

/** Fine buckets for work that must fit in a 16.7 ms tick. */
const TICK_SECONDS = [0.00005, 0.0001, 0.00025, 0.0005, 0.001, 0.002, 0.003, 0.004, 0.006, 0.008, 0.012, 0.0167, 0.025, 0.05]
const LAG_SECONDS = [0.0005, 0.001, 0.002, 0.004, 0.008, 0.0167, 0.033, 0.05, 0.1, 0.25, 0.5, 1]

/** Every metric's name starts with this, prom-client's process and Node.js metrics too. */
export const METRIC_PREFIX = 'plinko_'

/**
 * The server's Prometheus metrics, on their own Registry so several apps in
 * one process (tests) never share or clash.
 * @param {{ defaultMetrics?: boolean }} [options]
 */
export function createMetrics ({ defaultMetrics = true } = {}) {
  const registry = new Registry()
  const registers = [registry]
  // prom-client's own names already say what they measure (process_cpu_seconds_total,
  // nodejs_heap_size_used_bytes): one prefix, plinko_, as every other metric here.
  if (defaultMetrics) collectDefaultMetrics({ register: registry, prefix: METRIC_PREFIX })
  const messagesOut = new Counter({ name: 'plinko_ws_messages_out_total', help: 'WebSocket messages sent, by type', labelNames: ['type'], registers })
  return {
    registry,
    rooms: new Gauge({ name: 'plinko_rooms', help: 'Rooms alive', registers }),
    clients: new Gauge({ name: 'plinko_ws_clients', help: 'Open WebSocket connections', registers }),
    addressShareWorkers: new Gauge({ name: 'plinko_ws_address_limit_workers', help: 'Processes dividing the per-address WebSocket budgets (this one enforces 1/N of each)', registers }),
    ballsInFlight: new Gauge({ name: 'plinko_balls_in_flight', help: 'Balls in flight across all rooms', registers }),
    settlementsWaiting: new Gauge({ name: 'plinko_settlements_waiting', help: 'Payouts the ledger refused, waiting for their retry (/api/health says degraded meanwhile)', registers }),
    tickDuration: new Histogram({ name: 'plinko_tick_duration_seconds', help: 'Work per 60 Hz tick: stepping every room and broadcasting snapshots', buckets: TICK_SECONDS, registers }),
    tickLag: new Histogram({ name: 'plinko_tick_lag_seconds', help: 'How late each tick started after its scheduled time', buckets: LAG_SECONDS, registers }),
    tickLagCurrent: new Gauge({ name: 'plinko_tick_lag_current_seconds', help: 'Lag of the most recent tick', registers }),
    ticks: new Counter({ name: 'plinko_ticks_total', help: 'Ticks run', registers }),
    droppedTicks: new Counter({ name: 'plinko_ticks_dropped_total', help: 'Ticks skipped because the process stalled longer than the catch-up limit', registers }),
    commitDuration: new Histogram({ name: 'plinko_ledger_commit_seconds', help: 'Duration of one group-commit transaction', buckets: TICK_SECONDS, registers }),
    commitFailures: new Counter({ name: 'plinko_ledger_commit_failures_total', help: 'Group commits that failed and were rolled back', registers }),
    drops: new Counter({ name: 'plinko_drops_total', help: 'Drops recorded and announced', registers }),
    settles: new Counter({ name: 'plinko_settles_total', help: 'Drops settled and credited', registers }),
    betTotal: new Counter({ name: 'plinko_bet_credits_total', help: 'Credits bet on recorded drops', registers }),
    payoutTotal: new Counter({ name: 'plinko_payout_credits_total', help: 'Credits paid out on settled drops', registers }),
    messagesIn: new Counter({ name: 'plinko_ws_messages_in_total', help: 'WebSocket messages received, by type', labelNames: ['type'], registers }),
    messagesOut,
    bytesOut: new Counter({ name: 'plinko_ws_bytes_out_total', help: 'WebSocket payload bytes sent', registers }),
    snapshotsSkipped: new Counter({ name: 'plinko_snapshots_skipped_total', help: 'Snapshots not sent to a client because its send buffer was over the soft limit', registers }),
    slowConsumersClosed: new Counter({ name: 'plinko_ws_slow_consumers_closed_total', help: 'Connections closed because their send buffer passed the hard limit', registers }),
    httpConnections: new Gauge({ name: 'plinko_http_connections', help: 'Open HTTP connections (upgraded WebSockets included)', registers }),
    httpConnectionsShed: new Counter({ name: 'plinko_http_connections_shed_total', help: 'Idle HTTP connections closed to make room for a new one, by the cap reached (per_address or total)', labelNames: ['reason'], registers }),
    httpConnectionsRefused: new Counter({ name: 'plinko_http_connections_refused_total', help: 'New HTTP connections refused at a cap with none idle to shed, by the cap (per_address or total)', labelNames: ['reason'], registers }),
    authFailures: new Counter({ name: 'plinko_auth_failures_total', help: 'Wrong operator or session tokens presented, by kind', labelNames: ['kind'], registers }),
    authThrottled: new Counter({ name: 'plinko_auth_throttled_total', help: 'Authenticating requests refused with 429 because their address had too many wrong tokens, by kind', labelNames: ['kind'], registers }),
    errors: new Counter({ name: 'plinko_errors_total', help: 'Protocol and HTTP errors returned, by code', labelNames: ['code'], registers }),
    /** Pre-bound children for the hot path (label lookup once). */
    snapshotOut: messagesOut.labels('snapshot'),
    dropEventsOut: messagesOut.labels('drop_events')
  }
}

/** @typedef {ReturnType<typeof createMetrics>} Metrics */
