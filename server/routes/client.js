import fs from 'node:fs'
import path from 'node:path'
import fastifyStatic from '@fastify/static'

/**
 * The browser client, if one has been built into `clientDir`: `/` serves
 * index.html, `/audit` serves audit.html, `/share/:id/:token` share.html
 * (a shared drop, routes/share.js), other files by path. A missing or
 * empty folder registers nothing (the API works without a client).
 * @param {import('fastify').FastifyInstance} app
 * @param {{ clientDir: string }} options
 */
export default async function clientRoutes (app, { clientDir }) {
  let files = []
  try {
    files = fs.readdirSync(clientDir)
  } catch {
    app.log.info({ clientDir }, 'no client folder; serving the API only')
    return
  }
  if (files.length === 0) {
    app.log.info({ clientDir }, 'client folder is empty; serving the API only')
    return
  }
  await app.register(fastifyStatic, { root: path.resolve(clientDir), index: ['index.html'], wildcard: true })
  if (files.includes('audit.html')) {
    app.get('/audit', { schema: { summary: 'Operator audit page' } }, (request, reply) => reply.sendFile('audit.html'))
  }
  if (files.includes('share.html')) {
    app.get('/share/:id/:token', { schema: { summary: 'A shared drop, replayed and verified in the viewer\'s browser' } }, (request, reply) => reply.sendFile('share.html'))
  }
}
