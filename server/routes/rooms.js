import { ROOM_IDS } from '../rooms/room-id.js'

/**
 * GET /api/rooms: rooms alive now, and every room id that can be joined.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ arena: import('../arena.js').Arena }} options
 */
export default async function roomRoutes (app, { arena }) {
  app.get('/api/rooms', {
    schema: {
      summary: 'Rooms alive now (created on first join, disposed when empty) and all joinable ids',
      response: {
        200: {
          type: 'object',
          properties: {
            rooms: {
              type: 'array',
              items: {
                type: 'object',
                properties: {
                  id: { type: 'string' },
                  rows: { type: 'integer' },
                  risk: { type: 'string' },
                  players: { type: 'integer' },
                  ballsInFlight: { type: 'integer' },
                  tick: { type: 'integer' }
                }
              }
            },
            roomIds: { type: 'array', items: { type: 'string' } }
          }
        }
      }
    }
  }, async () => ({ rooms: [...arena.rooms.values()].map((room) => room.summary()), roomIds: ROOM_IDS }))
}
