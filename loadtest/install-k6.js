#!/usr/bin/env node
/**
 * `npm run loadtest:install`: builds k6 from its Go module into
 * loadtest/bin/k6 (`GOBIN=loadtest/bin go install go.k6.io/k6@v1.8.1`).
 * Needs Go and the Go module proxy; takes about two minutes the first time.
 * Does nothing when the right version is already there (--force rebuilds).
 */
import fs from 'node:fs'
import { spawnSync } from 'node:child_process'
import { K6_BIN_DIR, K6_MODULE, K6_PATH, K6_VERSION, k6VersionOf } from './driver/k6-binary.js'

const force = process.argv.includes('--force')
const existing = fs.existsSync(K6_PATH) ? k6VersionOf(K6_PATH) : null
if (existing?.startsWith(`k6 ${K6_VERSION} `) && !force) {
  console.log(`${existing} already at ${K6_PATH}`)
  process.exit(0)
}

const go = spawnSync('go', ['version'], { encoding: 'utf8' })
if (go.status !== 0) {
  console.error('go not found on PATH: k6 is built from its Go module (https://go.dev/doc/install)')
  process.exit(1)
}
fs.mkdirSync(K6_BIN_DIR, { recursive: true })
console.log(`building ${K6_MODULE}@${K6_VERSION} with ${go.stdout.trim()} into ${K6_BIN_DIR} …`)
const started = Date.now()
const build = spawnSync('go', ['install', `${K6_MODULE}@${K6_VERSION}`], {
  stdio: 'inherit',
  env: { ...process.env, GOBIN: K6_BIN_DIR }
})
if (build.status !== 0) {
  console.error(`go install failed (exit ${build.status ?? build.signal})`)
  process.exit(1)
}
console.log(`${k6VersionOf(K6_PATH)} built in ${Math.round((Date.now() - started) / 1000)} s: ${K6_PATH}`)
