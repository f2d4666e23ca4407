import fs from 'node:fs'
import path from 'node:path'

/**
 * Raised at start when SQLite could not keep its files where DATABASE_URL
 * points; names the directory and the cause (SQLite itself says only
 * "unable to open database file").
 */
export class DataDirectoryError extends Error {
  /** @param {string} message @param {NodeJS.ErrnoException} cause */
  constructor (message, cause) {
    super(message, { cause })
    this.name = 'DataDirectoryError'
    this.code = 'E_DATA_DIRECTORY'
  }
}

const CAUSES = {
  EROFS: 'is on a read-only file system',
  EACCES: 'is not writable by this process',
  EPERM: 'is not writable by this process',
  ENOSPC: 'has no space left',
  ENOTDIR: 'is not a directory',
  EEXIST: 'is not a directory', // mkdir -p over a file
  EDQUOT: 'is over its disk quota'
}

/**
 * Before any SQLite driver opens `file`: its directory exists (made if
 * not) and takes new files, since SQLite creates the database and, in WAL
 * mode, its -wal and -shm files beside it; an existing database file must
 * be readable and writable. Throws DataDirectoryError naming the cause.
 * @param {string} file the database file's path, or ':memory:'
 */
export function checkDataDirectory (file) {
  if (file === ':memory:') return
  const directory = path.dirname(file)
  const refuse = (error, what = `the data directory ${directory}`) => {
    const cause = CAUSES[error.code] ?? `cannot be used (${error.code ?? error.message})`
    throw new DataDirectoryError(`${what} ${cause}: SQLite keeps ${path.basename(file)} and its -wal and -shm files there; make it writable or point DATABASE_URL=sqlite:PATH elsewhere`, error)
  }
  try {
    fs.mkdirSync(directory, { recursive: true })
  } catch (error) {
    refuse(error)
  }
  // A real probe rather than access(W_OK): that says yes to root on a read-only mount.
  const probe = path.join(directory, `.plinko-write-check-${process.pid}`)
  try {
    fs.closeSync(fs.openSync(probe, 'wx'))
    fs.unlinkSync(probe)
  } catch (error) {
    if (error.code !== 'EEXIST') refuse(error)
  }
  try {
    fs.accessSync(file, fs.constants.R_OK | fs.constants.W_OK)
  } catch (error) {
    if (error.code !== 'ENOENT') refuse(error, `the database file ${file}`)
  }
}
