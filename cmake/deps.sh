#!/usr/bin/env bash
# Installs what grip needs from Debian's packages, once: Eigen 3.4, doctest 2.4, Google
# Benchmark, a compiler pair and CMake. Extra package names may be passed as arguments.
# Idempotent: packages already present are not reinstalled. MuJoCo (libmujoco-dev, for the
# optional component grip::mujoco) is installed where the distribution has it (Debian 12,
# Ubuntu 23.04 and newer).
set -euo pipefail
want=(libeigen3-dev doctest-dev libbenchmark-dev cmake g++ clang "$@")
optional=(libmujoco-dev)
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${want[@]}"; do
  installed "$p" || missing+=("$p")
done
for p in "${optional[@]}"; do
  installed "$p" || ! apt-cache show "$p" > /dev/null 2>&1 || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
for p in "${optional[@]}"; do  # the package lists may only now know it
  installed "$p" || ! apt-cache show "$p" > /dev/null 2>&1 || [[ " ${missing[*]} " == *" $p "* ]] || missing+=("$p")
done
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
