/**
 * GET /metrics: Prometheus text format from the app's own registry.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ metrics: import('../metrics.js').Metrics }} options
 */
export default async function metricsRoutes (app, { metrics }) {
  app.get('/metrics', {
    config: { rateLimit: false },
    schema: { summary: 'Prometheus metrics (text exposition format)' }
  }, async (request, reply) => {
    reply.type(metrics.registry.contentType)
    return metrics.registry.metrics()
  })
}
