import fs from 'node:fs'
import path from 'node:path'
import { execFileSync } from 'node:child_process'
import { fileURLToPath } from 'node:url'

/** The k6 release the scripts are written for, built from its Go module. */
export const K6_MODULE = 'go.k6.io/k6'
export const K6_VERSION = 'v1.8.1'
/** Where `npm run loadtest:install` puts it (git-ignored). */
export const K6_BIN_DIR = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..', 'bin')
export const K6_PATH = path.join(K6_BIN_DIR, 'k6')

/**
 * The k6 binary to run: $K6_BIN if set, else loadtest/bin/k6.
 * @returns {string}
 * @throws when it is missing, with the command that builds it
 */
export function k6Binary () {
  const file = process.env.K6_BIN || K6_PATH
  if (!fs.existsSync(file)) throw new Error(`k6 not found at ${file}: run \`npm run loadtest:install\` (builds ${K6_MODULE}@${K6_VERSION} with Go, about 2 minutes)`)
  return file
}

/** `k6 version` of a binary, or null if it does not run. @param {string} file */
export function k6VersionOf (file) {
  try {
    return execFileSync(file, ['version'], { encoding: 'utf8', timeout: 10_000 }).trim()
  } catch {
    return null
  }
}
