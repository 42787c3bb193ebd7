#!/usr/bin/env bash
# Fetches the real test and benchmark data from Debian packages into a cache
# directory outside the repository (never committed, never written into the tree):
#
#   $DIR/maps/{oa_dm4,ctf_inyard,czest3ctf}.bsp       Quake III maps (openarena-081-maps)
#   $DIR/meshes/{bunny00,armadillo,refined_elephant}.off   CGAL demo meshes (libcgal-demo)
#   $DIR/pk3/{pak0,pak4-textures}.pk3   the maps' textures and shader scripts
#                                       (openarena-data, openarena-081-textures)
#
# The maps find their textures in ../pk3 beside maps/ (scene/q3_textures.c);
# the archives are read in place, nothing is unpacked.
#
# DIR is $RTT_DATA_DIR, default $HOME/.cache/rtt-data.  Idempotent: whatever is
# already there is kept.  Prints the data directory on success; on failure says
# what went wrong on stderr and exits non-zero.
#
# Usage: bench/fetch-scenes.sh [--help]
set -euo pipefail
shopt -s inherit_errexit

DIR="${RTT_DATA_DIR:-$HOME/.cache/rtt-data}"
MAPS=(oa_dm4 ctf_inyard czest3ctf)
MESHES=(bunny00 armadillo refined_elephant)
PK3S=(pak0 pak4-textures)

die() { echo "fetch-scenes: $*" >&2; exit 1; }

if [[ "${1:-}" == "--help" || "${1:-}" == "-h" ]]; then
    sed -n '2,17p' "$0" | sed 's/^# \{0,1\}//'
    exit 0
fi
[[ $# -eq 0 ]] || { echo "usage: $0 [--help]" >&2; exit 2; }

for tool in apt-get dpkg-deb unzip find; do
    command -v "$tool" >/dev/null 2>&1 || die "'$tool' is not installed"
done

have_all() { # kind ext names...
    local kind=$1 ext=$2; shift 2
    local name
    for name in "$@"; do [[ -s "$DIR/$kind/$name.$ext" ]] || return 1; done
}

if have_all maps bsp "${MAPS[@]}" && have_all meshes off "${MESHES[@]}" && have_all pk3 pk3 "${PK3S[@]}"; then
    echo "$DIR"
    exit 0
fi

mkdir -p "$DIR/maps" "$DIR/meshes" "$DIR/pk3" "$DIR/packages" || die "cannot create $DIR"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/rtt-fetch.XXXXXX")" || die "cannot create a temporary directory"
trap 'rm -rf "$WORK"' EXIT
chmod 755 "$WORK" # apt-get download drops privileges to _apt when it can

as_root() {
    if [[ "$(id -u)" -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

# Downloads package $1 into $DIR/packages (kept, so reruns need no network).
download() {
    local pkg=$1 deb
    deb="$(find "$DIR/packages" -maxdepth 1 -name "${pkg}_*.deb" | head -n 1)"
    if [[ -n "$deb" ]]; then echo "$deb"; return 0; fi
    if ! (cd "$WORK" && apt-get download "$pkg" >"$WORK/apt.log" 2>&1); then
        echo "fetch-scenes: apt-get download $pkg failed; running apt-get update and retrying" >&2
        as_root apt-get update >"$WORK/update.log" 2>&1 || die "apt-get update failed (see: $(tail -n 1 "$WORK/update.log"))"
        (cd "$WORK" && apt-get download "$pkg" >"$WORK/apt.log" 2>&1) ||
            die "apt-get download $pkg failed: $(tail -n 1 "$WORK/apt.log")"
    fi
    deb="$(find "$WORK" -maxdepth 1 -name "${pkg}_*.deb" | head -n 1)"
    [[ -n "$deb" ]] || die "apt-get download $pkg produced no .deb"
    mv "$deb" "$DIR/packages/" || die "cannot move $deb into $DIR/packages"
    echo "$DIR/packages/$(basename "$deb")"
}

# Extracts package $1 into $WORK/$1 and prints that directory.
extract() {
    local pkg=$1 deb
    deb="$(download "$pkg")"
    mkdir -p "$WORK/$pkg"
    dpkg-deb -x "$deb" "$WORK/$pkg" || die "dpkg-deb -x $deb failed"
    echo "$WORK/$pkg"
}

fetch_maps() {
    have_all maps bsp "${MAPS[@]}" && return 0
    local root pk3 name
    root="$(extract openarena-081-maps)"
    pk3="$(find "$root" -name 'pak1-maps.pk3' | head -n 1)"
    [[ -n "$pk3" ]] || die "openarena-081-maps contains no pak1-maps.pk3"
    for name in "${MAPS[@]}"; do
        [[ -s "$DIR/maps/$name.bsp" ]] && continue
        unzip -o -q -j "$pk3" "maps/$name.bsp" -d "$WORK/maps" || die "maps/$name.bsp is not in $pk3"
        mv "$WORK/maps/$name.bsp" "$DIR/maps/$name.bsp.part" && mv "$DIR/maps/$name.bsp.part" "$DIR/maps/$name.bsp"
    done
}

# The CGAL demo package ships its data inside archives (libcgal-dev's
# data.tar.gz holds data/meshes/*.off); look for loose files first, then
# inside every tar.gz and zip archive, by file name.
find_mesh() { # root name
    local root=$1 name=$2 found archive member
    found="$(find "$root" -type f -name "$name.off" | head -n 1)"
    if [[ -n "$found" ]]; then echo "$found"; return 0; fi
    mkdir -p "$WORK/unpacked"
    while IFS= read -r archive; do
        member="$(tar -tzf "$archive" 2>/dev/null | grep -E "(^|/)$name\.off$" | head -n 1)" || true
        if [[ -n "$member" ]]; then
            tar -xzf "$archive" -C "$WORK/unpacked" "$member" || die "cannot extract $member from $archive"
            echo "$WORK/unpacked/$member"
            return 0
        fi
    done < <(find "$root" -type f \( -name '*.tar.gz' -o -name '*.tgz' \))
    while IFS= read -r archive; do
        member="$(unzip -Z1 "$archive" 2>/dev/null | grep -E "(^|/)$name\.off$" | head -n 1)" || true
        if [[ -n "$member" ]]; then
            unzip -o -q "$archive" "$member" -d "$WORK/unpacked" || die "cannot extract $member from $archive"
            echo "$WORK/unpacked/$member"
            return 0
        fi
    done < <(find "$root" -type f -name '*.zip')
    return 1
}

fetch_meshes() {
    have_all meshes off "${MESHES[@]}" && return 0
    local root name src
    root="$(extract libcgal-demo)"
    for name in "${MESHES[@]}"; do
        [[ -s "$DIR/meshes/$name.off" ]] && continue
        src="$(find_mesh "$root" "$name")" || die "libcgal-demo contains no $name.off"
        cp "$src" "$DIR/meshes/$name.off.part" && mv "$DIR/meshes/$name.off.part" "$DIR/meshes/$name.off"
    done
}

# The texture archives, copied whole from their packages' baseoa/.
fetch_textures() {
    have_all pk3 pk3 "${PK3S[@]}" && return 0
    local pkg root name src
    for pkg in openarena-data openarena-081-textures; do
        root="$(extract "$pkg")"
        for name in "${PK3S[@]}"; do
            [[ -s "$DIR/pk3/$name.pk3" ]] && continue
            src="$(find "$root" -path '*/baseoa/*' -name "$name.pk3" | head -n 1)"
            [[ -n "$src" ]] || continue
            cp "$src" "$DIR/pk3/$name.pk3.part" && mv "$DIR/pk3/$name.pk3.part" "$DIR/pk3/$name.pk3"
        done
    done
}

fetch_maps
fetch_meshes
fetch_textures
have_all maps bsp "${MAPS[@]}" && have_all meshes off "${MESHES[@]}" && have_all pk3 pk3 "${PK3S[@]}" ||
    die "some files are still missing in $DIR"
echo "$DIR"
