#!/usr/bin/env bash
# Fetch and build CNR-INM's L2-Sea (NATO AVT-331 L2 Sea benchmark: the WARP linear potential-flow solver)
# into a cache folder outside the repository. Idempotent: a second run with the binary present does nothing
# (pass --force to rebuild). Needs git, make, gfortran and LAPACK/BLAS:
#     apt-get install -y gfortran liblapack-dev libblas-dev
#
# Where:   $HULLOPT_L2SEA_DIR, else ${HULLOPT_CACHE:-~/.cache/hullopt}/l2sea
#          (src/ the checkout, bin/L2-Sea the binary, examples/DTMB-5415 the parent's input files)
# Source:  $L2SEA_REPO (a local clone or bare git dir of the public repository, for machines without
#          network), else https://github.com/MAORG-CNR-INM/NATO-AVT-331-L2-Sea-Benchmark
# Commit:  $L2SEA_COMMIT, else the one this was written against (below).
set -euo pipefail

URL=https://github.com/MAORG-CNR-INM/NATO-AVT-331-L2-Sea-Benchmark
COMMIT=${L2SEA_COMMIT:-01335ac8218287ad3333be5a0664bbfe1d0fa20f}   # "Add files via upload", 2023-03-29
DIR=${HULLOPT_L2SEA_DIR:-${HULLOPT_CACHE:-$HOME/.cache/hullopt}/l2sea}
SRC=$DIR/src
BIN=$DIR/bin/L2-Sea
FORCE=0
[[ "${1:-}" == "--force" ]] && FORCE=1

if [[ -x "$BIN" && $FORCE == 0 ]]; then
    echo "L2-Sea already built: $BIN (--force to rebuild)"
    exit 0
fi
for tool in git make gfortran; do
    command -v "$tool" >/dev/null || { echo "build.sh: $tool not found; on Debian/Ubuntu: apt-get install -y gfortran liblapack-dev libblas-dev git make" >&2; exit 2; }
done

mkdir -p "$DIR"
if [[ ! -d "$SRC/.git" ]]; then
    rm -rf "$SRC"
    origin=${L2SEA_REPO:-$URL}
    echo "cloning $origin -> $SRC"
    if ! git clone -q --no-checkout "$origin" "$SRC"; then
        cat >&2 <<MSG
build.sh: could not clone $origin.
Offline? Clone the public repository on a machine with network access
    git clone $URL
copy it here and point L2SEA_REPO at it (a clone or a bare git dir), then run this script again:
    L2SEA_REPO=/path/to/NATO-AVT-331-L2-Sea-Benchmark $0
MSG
        rm -rf "$SRC"; exit 3
    fi
fi
# Check out only what the build and the runs need: the repository also holds large files (PDFs, the KLE
# eigenvector table eigenvecto.out) that some mirrors lack and that we do not use.
git -C "$SRC" checkout -q "$COMMIT" -- LICENSE README.md Makefile src scripts \
    examples/DTMB-5415/5415_90_25_fs.x examples/DTMB-5415/SBDF.nml examples/DTMB-5415/alfak.out \
    examples/DTMB-5415/variables.inp

# Build out of the checkout (the upstream Makefile, set for gfortran -llapack -lblas, writes lib/*.a and
# bin/L2-Sea beside its sources; do not pass LIB= on the command line: the sub-makes use LIB too).
# -fno-automatic -finit-local-zero: the Fortran 77 code relies on local variables keeping their values between
# calls (and starting at zero). Built as upstream does (-O3 -fopenmp, locals on the stack) it reads garbage: two
# grids 1 mm apart gave C_W 1.14e-3 and 3.87e-3, and a second Froude number crashed with heap corruption; with
# static locals it agrees with an -O0 -fcheck=bounds build. Static locals are not thread-safe, so no OpenMP
# (FCOPTOMP empty): L2-Sea runs on one core.
FCOPT_L2SEA=${L2SEA_FCOPT:--O3 -fno-automatic -finit-local-zero}
BUILD=$DIR/build
rm -rf "$BUILD"; mkdir -p "$BUILD/lib" "$BUILD/bin"
cp -r "$SRC/src" "$SRC/Makefile" "$BUILD/"
( cd "$BUILD" && make FCOPT="$FCOPT_L2SEA" FCOPTOMP= > make.log 2>&1 ) || {
    echo "build.sh: make failed; see $BUILD/make.log" >&2; tail -20 "$BUILD/make.log" >&2; exit 4; }
mkdir -p "$DIR/bin" "$DIR/examples"
cp "$BUILD/bin/L2-Sea" "$BIN.tmp" && mv "$BIN.tmp" "$BIN"
rm -rf "$DIR/examples/DTMB-5415"; cp -r "$SRC/examples/DTMB-5415" "$DIR/examples/"
cp "$SRC/LICENSE" "$DIR/LICENSE"
echo "$COMMIT" > "$DIR/COMMIT"
echo "built $BIN (L2-Sea $COMMIT). Run it with 'ulimit -s unlimited' (benchmarks/l2sea/l2sea.py does)."
