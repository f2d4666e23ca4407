#!/usr/bin/env bash
# Fuzzes the HTTP API against its own description (/api/openapi.json), on a
# real server: a throwaway `node server/server.js` on 127.0.0.1 over SQLite in
# a temporary folder, with the client's pages served and every per-address
# limit lifted (tools/lifted-limits.js: every request comes from 127.0.0.1).
#
# The fuzzer is Schemathesis (from PyPI, pinned below). Why this one: it reads
# OpenAPI 3.1 as published (JSON Schema 2020-12 keywords, form-exploded query
# objects, per-operation security schemes, so one run carries the player's
# token on the player routes and the operator's on the audit routes); it
# checks both directions (schema-valid requests must be accepted, invalid ones
# refused), sends every path the methods it lacks (405 + Allow expected) and
# checks each answer's status, content type, headers and body against the
# description; a run is reproducible from its seed; and it installs from a
# registry this machine reaches (pip) with no other runtime to add. Any
# finding fails the run.
#
# Bounded: at most FUZZ_EXAMPLES cases per operation (default 40) and
# FUZZ_MAX_TIME seconds (default 180). Replay a failure with the seed it
# prints: FUZZ_SEED=… scripts/fuzz-api.sh. Schemathesis lives in a venv
# outside the project (PLINKO_SCHEMATHESIS_VENV, default ~/.cache/plinko-schemathesis).
set -euo pipefail
cd "$(dirname "$0")/.."

SCHEMATHESIS_VERSION=4.32.5
VENV="${PLINKO_SCHEMATHESIS_VENV:-$HOME/.cache/plinko-schemathesis}"
EXAMPLES="${FUZZ_EXAMPLES:-40}"
MAX_TIME="${FUZZ_MAX_TIME:-180}"
SEED="${FUZZ_SEED:-$(od -An -N4 -tu4 /dev/urandom | tr -d ' ')}"

if [ "$("$VENV/bin/schemathesis" --version 2>/dev/null)" != "schemathesis, version $SCHEMATHESIS_VERSION" ]; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install --quiet --disable-pip-version-check "schemathesis==$SCHEMATHESIS_VERSION"
fi

work="$(mktemp -d)"
server_pid=
# Stops the server (a graceful SIGTERM) and removes its folder; the run's own status stands.
stop () {
  if [ -n "$server_pid" ]; then
    kill "$server_pid" 2>/dev/null || true
    wait "$server_pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap stop EXIT

# The same lifted limits as every other launcher, from their one copy.
eval "$(node --input-type=module -e "import { LIFTED_LIMITS } from './tools/lifted-limits.js'; for (const [name, value] of Object.entries(LIFTED_LIMITS)) console.log('export ' + name + '=' + JSON.stringify(value))")"
export OPERATOR_TOKEN="fuzz-operator-$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')"
DATABASE_URL="sqlite:$work/plinko.sqlite" PORT=0 HOST=127.0.0.1 LOG_LEVEL=info LOG_FORMAT=json CLIENT_DIR=client \
  node server/server.js >"$work/server.log" 2>&1 &
server_pid=$!
port=
for _ in $(seq 1 300); do
  port="$(sed -n 's/.*listening at http:\/\/127\.0\.0\.1:\([0-9]*\).*/\1/p' "$work/server.log" | head -n 1)"
  [ -n "$port" ] && break
  kill -0 "$server_pid" 2>/dev/null || { cat "$work/server.log"; echo "the server exited before listening"; exit 1; }
  sleep 0.1
done
[ -n "$port" ] || { cat "$work/server.log"; echo "the server did not listen within 30 s"; exit 1; }
base="http://127.0.0.1:$port"
# A guest session's token for the player routes (POST /api/session: 201 { token, … }).
PLAYER_TOKEN="$(node -e "fetch(process.argv[1], { method: 'POST' }).then(async (r) => { if (r.status !== 201) throw new Error('POST /api/session: ' + r.status); console.log((await r.json()).token) })" "$base/api/session")"
export PLAYER_TOKEN

echo "fuzzing $base/api/openapi.json: schemathesis $SCHEMATHESIS_VERSION, seed $SEED, $EXAMPLES examples per operation, at most ${MAX_TIME}s"
replay="FUZZ_SEED=$SEED FUZZ_EXAMPLES=$EXAMPLES FUZZ_MAX_TIME=$MAX_TIME scripts/fuzz-api.sh${*:+ $*}"
echo "replay with: $replay"
status=0
# Through scripts/fuzz-report.js: same output, ending with a plain `Fuzz: N passed, N failed` line.
node scripts/fuzz-report.js -- "$VENV/bin/schemathesis" --config-file scripts/fuzz-api.toml run "$base/api/openapi.json" "$@" \
  --seed "$SEED" --max-examples "$EXAMPLES" --max-time "$MAX_TIME" \
  --workers 1 --generation-database none --no-color || status=$?
if ! kill -0 "$server_pid" 2>/dev/null; then
  cat "$work/server.log"
  echo "the server died during the fuzz run"
  status=1
fi
if [ "$status" != 0 ]; then
  # What the server itself logged as errors (a 5xx has its stack there).
  grep -E '"level":(50|60)' "$work/server.log" | tail -n 20 || true
  echo "fuzz run failed (seed $SEED): replay with $replay"
fi
exit "$status"
