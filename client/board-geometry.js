/**
 * Sizes of what is drawn around the physics, shared by the layout (the
 * main thread: board-renderer.js) and the drawing (board-painter.js, on
 * the main thread or in a worker). Units are 1/36 of a bucket's width
 * (board px on the 36 px buckets of engine 1.0.0), so every board,
 * whatever its scale, looks the same. Bucket boxes span from BUCKET_TOP
 * above the bucket line to `bucketBottom` below it (BUCKET_BOTTOM, or
 * UPRIGHT_BUCKET_BOTTOM when the labels stand upright to stay readable on
 * a narrow screen); the view ends a little lower.
 */
export const BUCKET_TOP = 4
export const BUCKET_BOTTOM = 22
export const VIEW_MARGIN_BOTTOM = 4
/**
 * Bucket labels are never drawn smaller than this (CSS px), from 320 to
 * 1920 px wide screens: a label that would be is written shorter, or the
 * labels stand upright in deeper buckets (board-renderer.js's layout).
 */
export const MIN_LABEL_PX = 11
export const LABEL_PX = 13
export const UPRIGHT_LABEL_PX = 11
/**
 * Bucket depth (units) when the labels stand upright: fixed, so the board's
 * shape on a phone is known ahead (style.css reserves it before any script
 * runs); deep enough for the 16-row boards' labels without their × at
 * MIN_LABEL_PX on a 320 px screen ("0.52", "1k").
 */
export const UPRIGHT_BUCKET_BOTTOM = 72

/** Board px per drawing unit on `board`. @param {{ bucketWidth: number }} board */
export function unitOf (board) {
  return board.bucketWidth / 36
}

/** The bucket labels' font at `px` (CSS px, or board px under the drawing's transform). */
export function labelFont (px) {
  return `700 ${px}px system-ui, sans-serif`
}

/** A canvas off the page: an OffscreenCanvas where there is one (always in a worker), else a detached <canvas>. */
export function makeCanvas (width, height) {
  if (typeof OffscreenCanvas === 'function') return new OffscreenCanvas(width, height)
  const canvas = document.createElement('canvas')
  canvas.width = width
  canvas.height = height
  return canvas
}
