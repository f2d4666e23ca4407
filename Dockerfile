# The Plinko Arena server. Built by docker-compose.yml (two or more replicas
# behind nginx, with PostgreSQL and Redis); also runs alone:
#   docker build -t plinko-arena . && docker run -p 8080:8080 plinko-arena
FROM node:26-bookworm-slim
ENV NODE_ENV=production
WORKDIR /app
COPY package.json package-lock.json ./
# Production dependencies only: nothing to compile (SQLite is node:sqlite).
RUN npm ci --omit=dev && npm cache clean --force
COPY engine ./engine
COPY protocol ./protocol
COPY charts ./charts
COPY server ./server
COPY client ./client
COPY bin ./bin
USER node
ENV HOST=0.0.0.0 PORT=8080
EXPOSE 8080
HEALTHCHECK --interval=10s --timeout=3s --retries=3 CMD ["node", "-e", "fetch('http://127.0.0.1:'+(process.env.MONITORING_PORT||process.env.PORT||8080)+'/api/health').then(r=>process.exit(r.ok?0:1),()=>process.exit(1))"]
# SIGTERM: settles the balls in flight, gives the room leases back, exits.
STOPSIGNAL SIGTERM
CMD ["node", "server/server.js"]
