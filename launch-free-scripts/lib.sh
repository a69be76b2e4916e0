# Shared by the launch-free scripts (sourced). Finds or builds the node executables.
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)

# FIVEAXIS_BIN: a folder holding fiveaxis-commander/-simulator/-monitor; default: build them (release).
fiveaxis_bins() {
    if [ -n "${FIVEAXIS_BIN:-}" ]; then
        echo "$FIVEAXIS_BIN"
        return
    fi
    (cd "$root" && cargo build --release --locked -q -p fiveaxis-commander -p fiveaxis-simulator -p fiveaxis-monitor >&2)
    echo "$root/target/release"
}
