import { errors } from './schemas.js'

/**
 * GET /metrics: Prometheus text format from the app's own registry.
 * Rendering every metric costs far more than answering 429, so it has a
 * per-address budget of its own (MONITORING_RATE_LIMIT a minute): a
 * Prometheus scrape every few seconds fits many times over.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ metrics: import('../metrics.js').Metrics, rateLimit: number }} options
 */
export default async function metricsRoutes (app, { metrics, rateLimit }) {
  app.get('/metrics', {
    config: { rateLimit: { max: rateLimit, timeWindow: 60_000 } },
    schema: { summary: 'Prometheus metrics (text exposition format)', response: errors(429) }
  }, async (request, reply) => {
    reply.type(metrics.registry.contentType)
    return metrics.registry.metrics()
  })
}
