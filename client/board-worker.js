import { BoardPainter } from './board-painter.js'
import { WorkerRoom } from './board-worker-room.js'

/**
 * The board drawn in a worker, on the OffscreenCanvas the page handed over
 * (board-worker-client.js): the draw calls and their rasterisation leave
 * the page's main thread, which keeps the simulation and the layout.
 * Messages in: { type: 'canvas', canvas }, { type: 'layout', layout },
 * { type: 'clear' }, { type: 'frame', ... } (a PaintFrame with the effect
 * commands started since the last one), { type: 'pixels', id }. Out:
 * { type: 'drawn', poses, stats } per frame (the pose buffer handed
 * back for reuse; stats null if nothing was drawn), { type: 'pixels', id, width, height, data }.
 *
 * Seeds mode (board-worker-room.js): { type: 'seeds-open', generation, room,
 * rows, risk, engineVersion } starts the room's simulation here (replacing
 * any), { type: 'seeds-close' } ends it, { type: 'seeds-add', drop },
 * { type: 'seeds-complete', dropId }, { type: 'seeds-trace', on } and
 * { type: 'seeds-check', id, tick, hash } (answered { type: 'seeds-checked',
 * id, result }); a frame then carries `seedsTick` (the render tick) instead
 * of poses, and its `drawn` answer the room's FrameReport as `seeds`.
 */

/** @type {BoardPainter | null} */
let painter = null
/** @type {WorkerRoom | null} the joined room's simulation (seeds mode) */
let room = null
let generation = 0

const EMPTY = new Float64Array(0)

self.onmessage = ({ data }) => {
  switch (data.type) {
    case 'canvas':
      painter = new BoardPainter(data.canvas)
      break
    case 'layout':
      painter.setLayout(data.layout)
      break
    case 'clear':
      painter.clearEffects()
      break
    case 'frame': {
      for (const command of data.commands) painter.apply(command)
      if (data.seedsTick === undefined) {
        self.postMessage({ type: 'drawn', poses: data.poses, stats: painter.draw(data) }, [data.poses.buffer])
        break
      }
      const seeded = room ? room.frame(data.seedsTick) : null
      const stats = painter.draw({ ...data, poses: seeded?.poses ?? EMPTY, count: seeded?.count ?? 0 })
      self.postMessage({ type: 'drawn', poses: null, stats, seeds: seeded ? { generation, ...seeded.report } : null })
      break
    }
    case 'seeds-open':
      room = new WorkerRoom(data)
      generation = data.generation
      break
    case 'seeds-close':
      room = null
      break
    case 'seeds-add':
      room?.add(data.drop)
      break
    case 'seeds-complete':
      room?.complete(data.dropId)
      break
    case 'seeds-trace':
      room?.trace(data.on)
      break
    case 'seeds-check':
      self.postMessage({ type: 'seeds-checked', id: data.id, result: room && generation === data.generation ? room.check(data.tick, data.hash) : null })
      break
    case 'pixels': {
      // What the canvas shows, for tests (the page cannot read a canvas it handed over).
      const { width, height } = painter.canvas
      const image = width > 0 && height > 0 ? painter.context.getImageData(0, 0, width, height) : null
      const pixels = image ? image.data : new Uint8ClampedArray(0)
      self.postMessage({ type: 'pixels', id: data.id, width, height, data: pixels }, [pixels.buffer])
      break
    }
  }
}
