#!/bin/bash
# FreeCAD 1.0 (Debian trixie) and 1.1 (Debian unstable) for the test suite, from Debian's own
# packages: a root filesystem per suite made by mmdebstrap, and wrapper commands that run its
# FreeCAD in a private mount namespace so that nothing mounted for it is seen outside.
#
#   tests/freecad_roots.sh build DIR SUITE MIRROR PACKAGE...
#       Make the root filesystem DIR/root (unless DIR/stamp already records the same suite,
#       mirror and packages: then it is reused) and write the wrappers DIR/bin/{freecadcmd,
#       freecad,xvfb-run}.  A changed package list rebuilds it.  Needs root and mmdebstrap.
#   tests/freecad_roots.sh mirror
#       The Debian mirror of the host's apt sources (else http://deb.debian.org/debian).
#   tests/freecad_roots.sh run DIR COMMAND [ARG...]
#       Run COMMAND inside the root filesystem DIR/root (what the wrappers do).  In a new mount namespace
#       (unshare -m, private propagation): /proc, /dev, /sys, /tmp, $HOME, the working folder,
#       this checkout and every folder named in $CAM_FREECAD_BINDS (colon-separated) are
#       bind-mounted at their own paths, so FreeCAD sees the test's files, its HOME/Mod and the
#       checkout the workbench links to where the host has them.  The host's root is mounted at
#       /run/camwb-host, and each executable named in $CAM_FREECAD_HOST_EXES (colon-separated
#       host paths, e.g. the virtual environment's python that `cam-workbench freecad install`
#       records for the exports) is replaced at its path by a small script that runs the host's
#       one there (chroot back to the host, same working folder, same arguments): the command
#       line the exports call is the host's, as on a user's machine with the package installed.
#       The environment is passed through, except PATH (the root's own) and PYTHON*/LD_* values.
#
# The test harness (tests/freecad_support.py) uses DIR/bin when $CAM_FREECAD_ROOT names DIR;
# `make test` runs the FreeCAD tests once per root.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
CHECKOUT="$(dirname "$HERE")"
STAMP=stamp

die() { echo "freecad_roots.sh: $*" >&2; exit 2; }

write_wrappers() {
    local dir="$1" name
    mkdir -p "$dir/bin"
    for name in freecadcmd freecad xvfb-run; do
        cat > "$dir/bin/$name.new" <<EOF
#!/bin/sh
# $name of the FreeCAD root filesystem $dir/root (written by tests/freecad_roots.sh)
exec "$HERE/freecad_roots.sh" run "$dir" $name "\$@"
EOF
        chmod 755 "$dir/bin/$name.new"
        mv -f "$dir/bin/$name.new" "$dir/bin/$name"
    done
}

build() {
    [ $# -ge 4 ] || die "usage: build DIR SUITE MIRROR PACKAGE..."
    local dir="$1" suite="$2" mirror="$3"
    shift 3
    dir="$(realpath -m "$dir")"
    local want
    want="suite=$suite mirror=$mirror packages=$(printf '%s\n' "$@" | sort | tr '\n' ' ')"
    if [ -f "$dir/$STAMP" ] && [ "$(cat "$dir/$STAMP")" = "$want" ] && [ -e "$dir/root/usr/bin/freecadcmd" ]; then
        echo "FreeCAD root $dir: reused ($want)"
        write_wrappers "$dir"
        return 0
    fi
    [ "$(id -u)" = 0 ] || die "building a root filesystem needs root"
    command -v mmdebstrap >/dev/null || die "mmdebstrap is not installed (Debian package mmdebstrap)"
    local tmp="$dir/root.tmp" log="$dir/build.log" t0=$SECONDS includes
    mkdir -p "$dir"
    rm -rf "$tmp" "$dir/$STAMP"
    echo "FreeCAD root $dir: building $suite with mmdebstrap ($want); log in $log"
    includes="$(IFS=,; echo "$*")"
    # unstable's Release file carries a Valid-Until that a snapshot mirror may have passed
    if ! mmdebstrap --variant=apt --aptopt='Acquire::Check-Valid-Until "false"' \
            --include="$includes" "$suite" "$tmp" "$mirror" > "$log" 2>&1; then
        tail -n 30 "$log" >&2
        rm -rf "$tmp"
        die "mmdebstrap $suite from $mirror failed (no network, or the mirror lacks a package?); see $log"
    fi
    rm -rf "$dir/root"
    mv "$tmp" "$dir/root"
    echo "$want" > "$dir/$STAMP"
    write_wrappers "$dir"
    echo "FreeCAD root $dir: built in $((SECONDS - t0)) s, $(du -sh "$dir/root" | cut -f1)"
}

# ---- run: inside `unshare -m` ------------------------------------------------------------------
make_path() {  # make folder or file $2 exist inside root $1 without writing into the root's own
    local root="$1" path="$2" kind="$3" top
    [ -e "$root$path" ] && return 0
    top="/${path#/}"; top="${top#/}"; top="/${top%%/*}"
    [ -e "$root$top" ] || mkdir -p "$root$top"
    if ! mountpoint -q "$root$top" && [ -z "$(ls -A "$root$top")" ]; then
        mount -t tmpfs camwb "$root$top"   # a top-level folder the root leaves empty (/work, /home)
    fi
    if [ "$kind" = dir ]; then mkdir -p "$root$path"; else mkdir -p "$(dirname "$root$path")"; : > "$root$path"; fi
}

bind_path() {  # bind host folder $2 at the same path inside root $1 (unless already there)
    local root="$1" path="$2" p
    [ -n "$path" ] && [ -d "$path" ] || return 0
    path="$(realpath "$path")"
    case "$path" in /|/proc|/proc/*|/dev|/dev/*|/sys|/sys/*|/run/camwb-host*) return 0 ;; esac
    for p in "${BOUND[@]}"; do
        case "$path/" in "$p"/*) return 0 ;; esac
    done
    make_path "$root" "$path" dir
    mount --bind "$path" "$root$path"
    BOUND+=("$path")
}

bridge_exe() {  # make host executable $2 run (on the host) from its path inside root $1
    local root="$1" exe="$2"
    case "$exe" in /*) ;; *) return 0 ;; esac
    [ -x "$exe" ] || return 0
    # Where the chroot's path resolution leaves what the host and the root share: a virtual
    # environment's python is a symlink into the host's interpreter (/root/.pyenv/…, /usr/bin/…),
    # which inside the root dangles or names the root's own Python.  Relative links are followed
    # (they stay in the shared folder); the bridge goes on the first absolute link target.
    local at="$exe" t
    while [ -L "$at" ]; do
        t="$(readlink "$at")"
        case "$t" in /*) at="$t"; break ;; *) at="$(dirname "$at")/$t" ;; esac
    done
    make_path "$root" "$at" file
    local script="$RUNTMP/bridge.$RANDOM$RANDOM"
    cat > "$script" <<EOF
#!/bin/sh
# $exe of the host, run from inside a FreeCAD root (tests/freecad_roots.sh)
d="\$(pwd)"
exec chroot /run/camwb-host /bin/sh -c 'cd "\$0" 2>/dev/null || cd /; exec "\$@"' "\$d" "$exe" "\$@"
EOF
    chmod 755 "$script"
    mount --bind "$script" "$root$at"
}

inside() {  # in the private mount namespace
    local root="$1"; shift
    BOUND=()
    RUNTMP="$(mktemp -d /tmp/camwb-root.XXXXXX)"
    trap 'rm -rf "$RUNTMP"' EXIT
    mkdir -p "$root/run/camwb-host"
    mount --rbind / "$root/run/camwb-host"
    mount -t proc proc "$root/proc"
    mount --rbind /dev "$root/dev"
    mount --rbind /sys "$root/sys"
    mount --bind /tmp "$root/tmp"; BOUND+=(/tmp)
    local p
    bind_path "$root" "$HOME"
    bind_path "$root" "$PWD"
    bind_path "$root" "$CHECKOUT"
    IFS=: read -r -a extra <<< "${CAM_FREECAD_BINDS:-}"
    for p in "${extra[@]}"; do bind_path "$root" "$p"; done
    IFS=: read -r -a exes <<< "${CAM_FREECAD_HOST_EXES:-}"
    for p in "${exes[@]}"; do bridge_exe "$root" "$p"; done
    local cwd="$PWD"
    # the root's PATH; nothing of the host's Python or libraries
    local -a unset=()
    local v
    for v in $(compgen -e); do
        case "$v" in PYTHON*|LD_LIBRARY_PATH|LD_PRELOAD|VIRTUAL_ENV|CAM_FREECAD_*) unset+=(-u "$v") ;; esac
    done
    chroot "$root" /usr/bin/env "${unset[@]}" PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
        /bin/sh -c 'cd "$0" 2>/dev/null || cd /; exec "$@"' "$cwd" "$@"
}

run() {
    [ $# -ge 2 ] || die "usage: run DIR COMMAND [ARG...]"
    local dir
    dir="$(realpath "$1")"; shift
    [ -f "$dir/$STAMP" ] && [ -x "$dir/root/usr/bin/env" ] || die "$dir holds no built root (run: make freecad-roots)"
    [ "$(id -u)" = 0 ] || die "running FreeCAD in a root filesystem needs root (mount namespaces, chroot)"
    exec unshare -m --propagation private "$HERE/freecad_roots.sh" _inside "$dir/root" "$@"
}

mirror() {  # the host's Debian mirror (its apt sources), else deb.debian.org
    local uri
    uri="$( (cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources 2>/dev/null || true) |
           sed -n -e 's|^URIs:[[:space:]]*\(https\{0,1\}://[^[:space:]]*/debian\)/\{0,1\}[[:space:]]*$|\1|p' \
                  -e 's|^deb[[:space:]]\{1,\}\(\[[^]]*\][[:space:]]\{1,\}\)\{0,1\}\(https\{0,1\}://[^[:space:]]*/debian\)/\{0,1\}[[:space:]].*|\2|p' |
           head -n 1)" || true
    echo "${uri:-http://deb.debian.org/debian}"
}

case "${1:-}" in
    mirror) mirror ;;
    build) shift; build "$@" ;;
    run) shift; run "$@" ;;
    _inside) shift; inside "$@" ;;
    *) die "usage: $0 build DIR SUITE MIRROR PACKAGE... | run DIR COMMAND [ARG...]" ;;
esac
