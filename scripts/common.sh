# SPDX-License-Identifier: Apache-2.0
# shellcheck shell=bash
# Shared by scripts/demo and scripts/test (sourced, not run): the repository
# root, package installation, build parallelism and timed steps.

VDB_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VDB_JOBS="${VDB_JOBS:-$(nproc 2>/dev/null || echo 2)}"

# ccache keeps its files in the user's cache folder, shared by every clone of the project
# (paths are made relative to the clone's root), unless the caller chose a place.
export CCACHE_DIR="${CCACHE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/vdb-ccache}"
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$VDB_ROOT}"

vdb_die() {
    echo "error: $*" >&2
    exit 1
}

# Prints the given packages (default: those of scripts/packages.txt) that are not installed.
vdb_missing_packages() {
    local pkg status
    while read -r pkg; do
        status="$(dpkg-query -W -f='${db:Status-Status}' "$pkg" 2>/dev/null || true)"
        [[ "$status" == installed ]] || echo "$pkg"
    done < <(if (($# > 0)); then
        printf '%s\n' "$@"
    else
        sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' "$VDB_ROOT/scripts/packages.txt"
    fi)
}

# Installs the missing ones of the given packages (default: those of scripts/packages.txt)
# with apt-get, as root or through sudo; does nothing (and needs no privileges) when all are
# present.
vdb_ensure_packages() {
    if ! command -v dpkg-query >/dev/null || ! command -v apt-get >/dev/null; then
        echo "Not a Debian system: skipping package installation." >&2
        if (($# > 0)); then
            echo "Needed: $*" >&2
        else
            echo "Needed: $(sed -e 's/#.*//' -e '/^[[:space:]]*$/d' "$VDB_ROOT/scripts/packages.txt" |
                tr '\n' ' ')" >&2
        fi
        return 0
    fi

    local -a missing
    mapfile -t missing < <(vdb_missing_packages "$@")
    if ((${#missing[@]} == 0)); then
        echo "All needed packages are installed."
        return 0
    fi
    echo "Installing ${#missing[@]} missing package(s): ${missing[*]}"

    local -a sudo=()
    if ((EUID != 0)); then
        command -v sudo >/dev/null ||
            vdb_die "run as root, or install sudo, or install these packages: ${missing[*]}"
        # Without a terminal there is no one to type a password: fail instead of waiting.
        if [[ -t 0 ]]; then sudo=(sudo); else sudo=(sudo -n); fi
    fi
    local -a apt=("${sudo[@]}" env DEBIAN_FRONTEND=noninteractive
        apt-get -q -o DPkg::Lock::Timeout=600)
    "${apt[@]}" update
    "${apt[@]}" install -y --no-install-recommends "${missing[@]}"

    mapfile -t missing < <(vdb_missing_packages "$@")
    ((${#missing[@]} == 0)) || vdb_die "still missing after apt-get install: ${missing[*]}"
}

# ---- Timed steps ----

VDB_STEP_NAMES=()
VDB_STEP_TIMES=()
VDB_CURRENT_STEP=""

vdb_clock() {
    printf '%d:%02d' $(($1 / 60)) $(($1 % 60))
}

# vdb_step "Title" command args...: runs the command under a header and records its time.
vdb_step() {
    local title="$1"
    shift
    VDB_CURRENT_STEP="$title"
    printf '\n==== %s ====\n' "$title"
    local t0=$SECONDS
    "$@"
    local elapsed=$((SECONDS - t0))
    VDB_STEP_NAMES+=("$title")
    VDB_STEP_TIMES+=("$elapsed")
    VDB_CURRENT_STEP=""
    printf -- '---- %s: done in %s\n' "$title" "$(vdb_clock "$elapsed")"
}

vdb_print_summary() {
    local i
    printf '\n==== Summary ====\n'
    for i in "${!VDB_STEP_NAMES[@]}"; do
        printf '  %6s  %s\n' "$(vdb_clock "${VDB_STEP_TIMES[$i]}")" "${VDB_STEP_NAMES[$i]}"
    done
    printf '  %6s  total\n' "$(vdb_clock "$SECONDS")"
}

# Install with `trap vdb_on_exit EXIT`: prints the summary, then VDB_SUCCESS_MESSAGE
# or the step that failed.
VDB_SUCCESS_MESSAGE="Done."
vdb_on_exit() {
    local rc=$?
    vdb_print_summary
    if ((rc == 0)); then
        printf '\n%s\n' "$VDB_SUCCESS_MESSAGE"
    else
        printf '\nFAILED%s (exit status %d)\n' \
            "${VDB_CURRENT_STEP:+ in step: $VDB_CURRENT_STEP}" "$rc" >&2
    fi
    return "$rc"
}
