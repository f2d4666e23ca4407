/**
 * The custom k6 metrics every player scenario reports. Per-message counts
 * are kept in the VU and added once when the player leaves (a sample per
 * message would cost k6 more CPU than the server spends sending it);
 * per-drop figures are recorded as they happen.
 */
import { Counter, Trend } from 'k6/metrics'

export const metrics = {
  /** Errors by `code` tag: server codes (E_…), HTTP_<status>, WS_CLOSE_<code>, WS_ERROR, and X_… for checks the client made. */
  errors: new Counter('plinko_errors'),
  /** drop sent → own `dropped` received (recorded and announced). */
  dropAck: new Trend('drop_ack_ms', true),
  /** drop sent → own `settled` received (includes the ball's flight, 2–5 s). */
  dropSettled: new Trend('drop_settled_ms', true),
  /** drop→settled minus the ball's flight ((ticks − 1) / 60 s: it starts on the next tick): what the server adds. */
  dropSettleOverhead: new Trend('drop_settle_overhead_ms', true),
  /** Time between two consecutive snapshot frames (sampled). */
  snapshotInterval: new Trend('snapshot_interval_ms', true),
  /** |interval − tick difference × 1/60 s| between two consecutive snapshot frames (sampled). */
  snapshotJitter: new Trend('snapshot_jitter_ms', true),
  /** Per client, over its connected time. */
  clientMessagesPerSecond: new Trend('client_msgs_per_s'),
  clientBytesPerSecond: new Trend('client_bytes_per_s'),
  /** Seeds mode: the other players' drops received in drop-events frames. */
  dropEventsReceived: new Counter('drop_events_received'),
  /** Totals by `kind` tag: json, snapshot, or drop_events (seeds mode). */
  messagesReceived: new Counter('messages_received'),
  bytesReceived: new Counter('bytes_received'),
  dropsSent: new Counter('drops_sent'),
  dropsSettled: new Counter('drops_settled'),
  /** Drops sent and accepted whose `settled` never came before the player left. */
  unsettledDrops: new Counter('unsettled_drops'),
  /** An own `dropped`/`settled` whose balance is not the previous balance − bet (+ payout). */
  balanceMismatches: new Counter('balance_mismatches'),
  /** Clustered: joins answered E_WRONG_NODE and followed to the owner (not errors). */
  redirects: new Counter('plinko_redirects')
}
