# Shared by examples/figure4.sh and examples/targets.sh (sourced, not run): the `--update-docs`
# flag, the build with the `render` feature, and a check that `spraysim render` works here.

# The `spraysim` these scripts run: the release build of this checkout.
bin=./target/release/spraysim

# Reads the script's arguments: `--update-docs`, or none. Sets `update_docs` to 1 or 0.
parse_args() {
    update_docs=0
    for arg in "$@"; do
        case "$arg" in
            --update-docs) update_docs=1 ;;
            -h | --help)
                sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'
                exit 0
                ;;
            *)
                echo "error: unknown argument $arg (usage: bash $0 [--update-docs])" >&2
                exit 2
                ;;
        esac
    done
}

# Builds `spraysim` with the `render` feature, then renders one small still of a very short run
# of the default scene into $1 to check that 3D views work on this machine; stops with a message
# saying what is missing when they do not.
require_render() {
    local probe="$1/render-check"
    echo "building spraysim with the render feature: cargo build --release --features render" >&2
    if ! cargo build --release --features render; then
        echo "error: \`cargo build --release --features render\` failed; these figures need the command's" >&2
        echo "       \`render\` feature (3D views on wgpu; see docs/3d.md)" >&2
        exit 1
    fi
    if ! "$bin" render -o "$probe" --at end --size 64x40 --set simulation.duration=0.01 -q; then
        echo "error: \`spraysim render\` does not work here (its message is above). It needs the" >&2
        echo "       \`render\` feature (\`cargo build --release --features render\`) and a graphics" >&2
        echo "       adapter: any GPU, or Mesa's software drivers (on Debian or Ubuntu:" >&2
        echo "       apt-get install mesa-vulkan-drivers libvulkan1 libegl1 libgl1-mesa-dri); see docs/3d.md" >&2
        exit 1
    fi
    rm -rf "$probe"
}
