import { ROOM_IDS } from '../../protocol/room-id.js'

/**
 * GET /api/rooms: rooms alive now, and every room id that can be joined.
 * @param {import('fastify').FastifyInstance} app
 * @param {{ ownership: import('../coordination/room-ownership.js').RoomOwnership }} services
 */
export default async function roomRoutes (app, { ownership }) {
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
                  tick: { type: 'integer' },
                  // Clustered only: the URL of the process running the room (connect to OWNER/ws).
                  owner: { type: ['string', 'null'] }
                }
              }
            },
            roomIds: { type: 'array', items: { type: 'string' } }
          }
        }
      }
    }
  }, async () => ({
    // Clustered, room ownership lists the rooms of every process.
    rooms: await ownership.list(),
    roomIds: ROOM_IDS
  }))
}
