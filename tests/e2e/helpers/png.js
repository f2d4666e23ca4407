import { inflateSync } from 'node:zlib'

/**
 * Just enough PNG decoding to check a screenshot is not blank: 8-bit
 * RGB/RGBA, non-interlaced (what Chromium writes), all five filters.
 * @param {Buffer} png
 * @returns {{ width: number, height: number, channels: number, pixels: Uint8Array }}
 */
export function decodePng (png) {
  if (png.readUInt32BE(0) !== 0x89504e47) throw new Error('not a PNG')
  let offset = 8
  let width = 0; let height = 0; let colorType = 0; let bitDepth = 0; let interlace = 0
  const data = []
  while (offset < png.length) {
    const length = png.readUInt32BE(offset)
    const type = png.toString('latin1', offset + 4, offset + 8)
    const body = png.subarray(offset + 8, offset + 8 + length)
    if (type === 'IHDR') {
      width = body.readUInt32BE(0)
      height = body.readUInt32BE(4)
      bitDepth = body[8]
      colorType = body[9]
      interlace = body[12]
    } else if (type === 'IDAT') {
      data.push(body)
    } else if (type === 'IEND') {
      break
    }
    offset += 12 + length
  }
  if (bitDepth !== 8 || interlace !== 0 || (colorType !== 2 && colorType !== 6)) {
    throw new Error(`unsupported PNG: bit depth ${bitDepth}, colour type ${colorType}, interlace ${interlace}`)
  }
  const channels = colorType === 6 ? 4 : 3
  const raw = inflateSync(Buffer.concat(data))
  const stride = width * channels
  const pixels = new Uint8Array(height * stride)
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)]
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1))
    const out = y * stride
    for (let x = 0; x < stride; x++) {
      const left = x >= channels ? pixels[out + x - channels] : 0
      const up = y > 0 ? pixels[out - stride + x] : 0
      const upLeft = y > 0 && x >= channels ? pixels[out - stride + x - channels] : 0
      let value = line[x]
      if (filter === 1) value += left
      else if (filter === 2) value += up
      else if (filter === 3) value += (left + up) >> 1
      else if (filter === 4) value += paeth(left, up, upLeft)
      pixels[out + x] = value & 0xff
    }
  }
  return { width, height, channels, pixels }
}

function paeth (a, b, c) {
  const p = a + b - c
  const pa = Math.abs(p - a); const pb = Math.abs(p - b); const pc = Math.abs(p - c)
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c)
}

/**
 * How much is on the image: distinct RGB colours and the share of pixels
 * that differ from the most common colour (the background).
 * @param {Buffer} png
 */
export function imageStats (png) {
  const { width, height, channels, pixels } = decodePng(png)
  const counts = new Map()
  for (let i = 0; i < pixels.length; i += channels) {
    const rgb = (pixels[i] << 16) | (pixels[i + 1] << 8) | pixels[i + 2]
    counts.set(rgb, (counts.get(rgb) ?? 0) + 1)
  }
  const total = width * height
  const background = Math.max(...counts.values())
  return { width, height, distinctColors: counts.size, nonBackgroundShare: 1 - background / total }
}
