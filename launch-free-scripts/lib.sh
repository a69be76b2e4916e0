# Shared by the launch-free scripts (sourced). Finds or builds the node executables.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)

# FIVEAXIS_BIN: a folder holding fiveaxis-commander/-simulator/-monitor; default: build them (release),
# and the extra packages named as arguments (e.g. fiveaxis_rerun, the slowest to build).
fiveaxis_bins() {
    if [ -n "${FIVEAXIS_BIN:-}" ]; then
        echo "$FIVEAXIS_BIN"
        return
    fi
    local pkgs=(-p fiveaxis_commander -p fiveaxis_simulator -p fiveaxis_monitor -p fiveaxis_recorder)
    for p in "$@"; do pkgs+=(-p "$p"); done
    (cd "$root" && cargo build --release --locked -q "${pkgs[@]}" >&2)
    echo "$root/target/release"
}
