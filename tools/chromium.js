/**
 * Debian's Chromium (apt-get install chromium), never a downloaded build:
 * how the e2e tests and the page scripts (scripts/page-load.js) start it.
 * CHROMIUM_PATH overrides the path.
 */
export const CHROMIUM_PATH = process.env.CHROMIUM_PATH || '/usr/bin/chromium'

/** Headless, sandbox off (containers run as root), and every networking feature that could reach out turned off. */
export const CHROMIUM_ARGS = [
  '--headless=new',
  '--no-sandbox',
  '--disable-gpu',
  '--disable-quic',
  '--no-first-run',
  '--disable-background-networking',
  '--disable-component-update',
  '--disable-sync'
]
