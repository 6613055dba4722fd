# nginx from Debian's package in front of the API replicas (docker/compose.scaled.yaml).
# Docker's DNS answers "api" with every replica; `resolve` needs nginx plus, so the
# upstream is resolved at start (restart the balancer after scaling the API).
FROM debian:bookworm-slim
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends nginx-light \
 && rm -rf /var/lib/apt/lists/*
COPY balancer.nginx.conf /etc/nginx/nginx.conf
EXPOSE 8080
CMD ["nginx", "-g", "daemon off;"]
