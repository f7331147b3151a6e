#!/usr/bin/env bash
# Installs what grip needs from Debian's packages, once: Eigen 3.4, doctest 2.4, Google
# Benchmark, a compiler pair and CMake. Extra package names may be passed as arguments.
# Idempotent: packages already present are not reinstalled.
set -euo pipefail
want=(libeigen3-dev doctest-dev libbenchmark-dev cmake g++ clang "$@")
missing=()
for p in "${want[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
