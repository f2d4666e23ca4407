import { toCredits, toMilli } from '/protocol/payout.js'
import { formatAmount, formatMultiplier, multiplierTitle, showAmount } from './dom.js'

const SVG = 'http://www.w3.org/2000/svg'
/** Points kept for the chart (older ones are merged away by sampling). */
const MAX_POINTS = 400

/**
 * The session panel: wagered, profit, drops and best multiplier since the
 * page opened (or the last reset), and a small chart of the profit after
 * each drop. Sums are kept in integer milli-credits (as the ledger keeps
 * them), so a session's profit is exact, not a float sum of decimals.
 */
export class SessionStats {
  /** @param {{ wagered: HTMLElement, profit: HTMLElement, drops: HTMLElement, best: HTMLElement, chart: SVGSVGElement }} views */
  constructor (views) {
    this.views = views
    this.reset()
  }

  reset () {
    this.wageredMilli = 0
    this.profitMilli = 0
    this.drops = 0
    this.best = null
    /** @type {number[]} profit after each drop, the first point 0 */
    this.curve = [0]
    this.render()
  }

  /** @param {{ bet: number, payout: number, multiplier: number }} result */
  add ({ bet, payout, multiplier }) {
    this.wageredMilli += toMilli(bet)
    this.profitMilli += toMilli(payout) - toMilli(bet)
    this.drops++
    this.best = this.best === null ? multiplier : Math.max(this.best, multiplier)
    this.curve.push(this.profit)
    if (this.curve.length > MAX_POINTS) this.curve = this.curve.filter((_, i) => i % 2 === 0 || i === this.curve.length - 1)
    this.render()
  }

  /** Credits wagered since the page opened (or the last reset). */
  get wagered () {
    return toCredits(this.wageredMilli)
  }

  /** Credits won minus credits wagered. */
  get profit () {
    return toCredits(this.profitMilli)
  }

  get summary () {
    return { wagered: this.wagered, profit: this.profit, drops: this.drops, best: this.best, points: this.curve.length }
  }

  render () {
    const v = this.views
    showAmount(v.wagered, this.wagered)
    showAmount(v.profit, this.profit, true)
    v.profit.className = this.profit > 0 ? 'win' : this.profit < 0 ? 'loss-red' : ''
    v.drops.textContent = formatAmount(this.drops)
    v.best.textContent = this.best === null ? '–' : formatMultiplier(this.best)
    const bestTitle = multiplierTitle(this.best)
    if (bestTitle) v.best.title = bestTitle
    else v.best.removeAttribute('title')
    this._chart()
  }

  _chart () {
    const chart = this.views.chart
    const width = 300
    const height = 70
    const pad = 4
    const values = this.curve
    const min = Math.min(0, ...values)
    const max = Math.max(0, ...values)
    const span = Math.max(1e-9, max - min)
    const x = (i) => pad + (width - 2 * pad) * (values.length === 1 ? 0 : i / (values.length - 1))
    const y = (v) => pad + (height - 2 * pad) * (1 - (v - min) / span)
    const points = values.map((v, i) => `${x(i).toFixed(1)},${y(v).toFixed(1)}`).join(' ')
    const up = this.profit >= 0
    const node = (tag, attributes) => {
      const n = document.createElementNS(SVG, tag)
      for (const [name, value] of Object.entries(attributes)) n.setAttribute(name, String(value))
      return n
    }
    chart.replaceChildren(
      node('line', { x1: 0, x2: width, y1: y(0), y2: y(0), stroke: '#46518a', 'stroke-width': 1, 'stroke-dasharray': '3 3', 'vector-effect': 'non-scaling-stroke' }),
      node('polyline', { points, fill: 'none', stroke: up ? '#4ade80' : '#ff6b6b', 'stroke-width': 2, 'stroke-linejoin': 'round', 'vector-effect': 'non-scaling-stroke', class: 'profit-line' })
    )
    chart.dataset.points = String(values.length)
  }
}

