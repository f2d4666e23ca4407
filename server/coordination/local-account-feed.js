/**
 * The account feed of a server that runs alone (account-feed.js): no other
 * process changes its accounts, so there is nothing to tell or to hear.
 * @implements {import('./account-feed.js').AccountFeed}
 */
export class LocalAccountFeed {
  async start () {}
  balancesCommitted () {}
  async seedRotated () {}
  async seedOutdated () {}
  async close () {}
}
