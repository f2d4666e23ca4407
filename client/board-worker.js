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
 * id, result }). The seeds room is drawn on the worker's own animation
 * frames (WorkerRoom.drive), opened with the page's time origin and
 * prefers-reduced-motion: the page sends no frames but
 * { type: 'seeds-clock', line } when its room clock moves, { type:
 * 'commands', commands } as effects start and { type: 'motion', reduced };
 * the worker answers { type: 'seeds-drawn', seeds } (a DrivenReport) when
 * something happened or its counters are due. Frames stop while nothing
 * moves and start again with the next message that changes the picture.
 */

/** @type {BoardPainter | null} */
let painter = null
/** @type {WorkerRoom | null} the joined room's simulation (seeds mode) */
let room = null
let generation = 0
/** The page's time origin, for frames the worker times itself (page time = this worker's origin + now − it). */
let pageTimeOrigin = 0
let reducedMotion = false
/** Something besides the balls changed since the seeds room's last frame. */
let changed = false
let frameRequested = false

const nextFrame = typeof self.requestAnimationFrame === 'function'
  ? (callback) => self.requestAnimationFrame(callback)
  : (callback) => setTimeout(callback, 16)

/** The seeds room needs a frame: one is asked for (once). */
function wake () {
  if (frameRequested || !room || !painter) return
  frameRequested = true
  nextFrame(drivenFrame)
}

function drivenFrame () {
  frameRequested = false
  if (!room || !painter) return
  const now = performance.timeOrigin + performance.now() - pageTimeOrigin
  const { report, moving } = room.drive(painter, now, { reducedMotion, changed })
  changed = false
  if (report) self.postMessage({ type: 'seeds-drawn', seeds: { generation, ...report } })
  if (moving) wake()
}

/** The picture changed besides the balls: the seeds room's next frame draws it. */
function changedPicture () {
  changed = true
  wake()
}

self.onmessage = ({ data }) => {
  switch (data.type) {
    case 'canvas':
      painter = new BoardPainter(data.canvas)
      break
    case 'layout':
      painter.setLayout(data.layout)
      changedPicture()
      break
    case 'clear':
      painter.clearEffects()
      changedPicture()
      break
    case 'commands':
      for (const command of data.commands) painter?.apply(command)
      changedPicture()
      break
    case 'motion':
      reducedMotion = data.reduced
      changedPicture()
      break
    case 'frame':
      for (const command of data.commands) painter.apply(command)
      self.postMessage({ type: 'drawn', poses: data.poses, stats: painter.draw(data) }, [data.poses.buffer])
      break
    case 'seeds-open':
      room = new WorkerRoom(data)
      generation = data.generation
      pageTimeOrigin = data.pageTimeOrigin
      reducedMotion = data.reducedMotion
      changedPicture()
      break
    case 'seeds-clock':
      if (room) room.line = data.line
      wake()
      break
    case 'seeds-close':
      room = null
      break
    case 'seeds-add':
      room?.add(data.drop)
      wake()
      break
    case 'seeds-complete':
      room?.complete(data.dropId)
      wake()
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
