#!/usr/bin/env bash
# @file deps.sh
# @brief Installs the Debian packages the build needs; a fast no-op when all are present.
#
# Usage: tools/build/deps.sh [base|bench|fuzz|study|slurm|model ...]   (default: base)
# Works as root or through sudo. Exits non-zero if a package cannot be installed.
set -euo pipefail

base_pkgs=(
  make g++ binutils pkg-config
  libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev
  libboost-dev
  cppcheck clang-tidy clang gcovr gnuplot-nox
  python3  # the test counts (tools/build/count_tests.py) and the bench summary
)
bench_pkgs=(libopencv-dev)
fuzz_pkgs=(clang libclang-rt-dev)
study_pkgs=(jq)
# A single-node Slurm cluster for campaigns (tools/slurm/): the controller, the
# node daemon, the commands, munge for their credentials, and procps for `free`.
slurm_pkgs=(slurmctld slurmd slurm-client munge procps)
# The TMR protocol's model (tools/model/): SPIN and the C compiler its verifiers are built with.
model_pkgs=(spin gcc python3)

groups=("$@")
[ ${#groups[@]} -gt 0 ] || groups=(base)

wanted=()
for g in "${groups[@]}"; do
  case "$g" in
    base)  wanted+=("${base_pkgs[@]}") ;;
    bench) wanted+=("${bench_pkgs[@]}") ;;
    fuzz)  wanted+=("${fuzz_pkgs[@]}") ;;
    study) wanted+=("${study_pkgs[@]}") ;;
    slurm) wanted+=("${slurm_pkgs[@]}") ;;
    model) wanted+=("${model_pkgs[@]}") ;;
    *) echo "deps: unknown package group '$g' (allowed: base bench fuzz study slurm model)" >&2; exit 2 ;;
  esac
done

# The wanted packages not fully installed ("install ok installed"), one per line.
missing_packages() {
  local p
  for p in "${wanted[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "$p"
    fi
  done
}

mapfile -t missing < <(missing_packages)
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
  sudo_cmd=()
elif command -v sudo >/dev/null 2>&1; then
  sudo_cmd=(sudo)
else
  echo "deps: missing ${missing[*]}: run 'make deps' as root (or with sudo)" >&2
  exit 1
fi

# Goals of one parallel make (or two makes) may both find packages missing: they
# install one at a time, and the second installs only what is still missing.
lock="${TMPDIR:-/tmp}/trn-deps.$(id -u).lock"
if exec 9>>"$lock"; then
  flock 9
  mapfile -t missing < <(missing_packages)
  [ ${#missing[@]} -eq 0 ] && exit 0
fi

echo "deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
