import { BoardPainter } from './board-painter.js'

/**
 * The board drawn in a worker, on the OffscreenCanvas the page handed over
 * (board-worker-client.js): the draw calls and their rasterisation leave
 * the page's main thread, which keeps the simulation and the layout.
 * Messages in: { type: 'canvas', canvas }, { type: 'layout', layout },
 * { type: 'clear' }, { type: 'frame', ... } (a PaintFrame with the effect
 * commands started since the last one), { type: 'pixels', id }. Out:
 * { type: 'drawn', poses, stats } per frame (the pose buffer handed
 * back for reuse; stats null if nothing was drawn), { type: 'pixels', id, width, height, data }.
 */

/** @type {BoardPainter | null} */
let painter = null

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
      self.postMessage({ type: 'drawn', poses: data.poses, stats: painter.draw(data) }, [data.poses.buffer])
      break
    }
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
