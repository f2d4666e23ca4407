import fs from 'node:fs'

/** The engine's published standard, as it is in the repository: what an auditor implements from. */
const SPEC_FILES = [
  { path: '/docs/engine-spec.md', file: new URL('../../docs/engine-spec.md', import.meta.url), type: 'text/markdown; charset=utf-8', body: { description: 'Markdown', content: { 'text/markdown': { schema: { type: 'string' } } } }, summary: 'The engine specification (every shipped version), as Markdown' },
  { path: '/docs/engine-spec-vectors.json', file: new URL('../../docs/engine-spec-vectors.json', import.meta.url), type: 'application/json; charset=utf-8', body: { description: 'JSON', content: { 'application/json': { schema: { type: 'object', additionalProperties: true } } } }, summary: "The specification's test vectors (drops by seed: bucket, ticks, state hashes after ticks 1, 10 and 100)" }
]

/**
 * GET /docs/engine-spec.md and /docs/engine-spec-vectors.json: the
 * specification an independent implementation is written from, served by
 * the server that decides the drops (read once at start), so the operator
 * page can link it and a player can read what their drop's physics is.
 * @param {import('fastify').FastifyInstance} app
 */
export default async function engineSpecRoutes (app) {
  for (const { path, file, type, body: shape, summary } of SPEC_FILES) {
    const body = fs.readFileSync(file)
    app.get(path, {
      schema: { summary, response: { 200: shape } }
    }, async (request, reply) => reply.type(type).header('cache-control', 'public, max-age=3600').send(body))
  }
}
