import fs from 'node:fs'
import path from 'node:path'
import fastifyStatic from '@fastify/static'

/**
 * The browser client, if one has been built into `clientDir`: its files by
 * path (the pages themselves, `/`, `/audit` and `/share/:id/:token`, with
 * versioned links, and the files they link to come from client-assets.js). A missing or
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
  await app.register(fastifyStatic, { root: path.resolve(clientDir), index: false, wildcard: true })
}
