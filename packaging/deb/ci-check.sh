#!/usr/bin/env bash
# Builds the Debian package from the binaries `cargo test --workspace`
# built (debug profile: this checks the package, it is not a release),
# lists and checks its contents, then unpacks it into a throw-away root
# where an unprivileged user runs the README's main job (the simulated
# mill) with the packaged binaries. Run from the workspace root by
# .ci/run; cargo-deb is installed if missing (about 2 minutes of CPU).
set -euo pipefail
cd "$(dirname "$0")/../.."

CARGO_DEB_VERSION=3.8.0
if ! cargo deb --version >/dev/null 2>&1; then
    cargo install cargo-deb --locked --version "$CARGO_DEB_VERSION" --no-default-features
fi

out=target/debian-ci
rm -rf "$out"
mkdir -p "$out"
cargo deb -p hal-tools --profile dev --no-build --fast -o "$out/" 2>&1 \
    | grep -v -e 'dev profile is not supported' -e 'To enable debug symbols' || true
deb=$(ls "$out"/hal-suite_*.deb)
echo "package: $deb"

fail() { echo "package check: $*" >&2; exit 1; }

listing=$(dpkg-deb -c "$deb")
has() { grep -q -E "[[:space:]]\./$1\$" <<<"$listing" || fail "missing $1"; }
# Every binary is packaged except the developers' benchmarks (*-bench).
for bin in tools/*/src/bin/*.rs drivers/*/src/bin/*.rs; do
    name=$(basename "$bin" .rs)
    case "$name" in *-bench) continue ;; esac
    has "usr/bin/$name"
done
has usr/lib/udev/rules.d/60-hal-suite.rules
has usr/lib/tmpfiles.d/hal.conf
has etc/security/limits.d/hal.conf
for page in packaging/man/*.1 packaging/man9/*.9; do
    base=$(basename "$page")
    has "usr/share/man/man${base##*.}/$base.gz"
done
has usr/share/hal/hallib/core_sim.hal
has usr/share/doc/hal-suite/examples/sim/mill.hal
# No setuid or setgid bit on anything; the host is not world-executable.
if awk '{print $1}' <<<"$listing" | grep -q '[sS]'; then
    fail "a file has a setuid or setgid bit"
fi
grep -q -E '^-rwxr-x--- .*\./usr/bin/hal-host$' <<<"$listing" || fail "hal-host is not 0750"

ctrl=$(mktemp -d)
dpkg-deb -e "$deb" "$ctrl"
[ -x "$ctrl/postinst" ] && [ -x "$ctrl/postrm" ] || fail "maintainer scripts missing"
grep -q 'addgroup --system hal' "$ctrl/postinst" || fail "postinst does not create the group hal"
grep -q 'setcap' "$ctrl/postinst" || fail "postinst gives no capabilities"
grep -qx '/etc/security/limits.d/hal.conf' "$ctrl/conffiles" || fail "limits.d is not a conffile"
rm -rf "$ctrl"
echo "package contents: ok"

# The throw-away root. The package's postinst would make hal-host
# root:hal; here the group nogroup stands in for hal.
root=$(mktemp -d)
trap 'rm -rf "$root"' EXIT
dpkg-deb -x "$deb" "$root"
chmod 755 "$root"
work="$root/work"
mkdir -p "$work/run"
cp -r "$root/usr/share/doc/hal-suite/examples/sim/." "$work/"
as_user=()
if [ "$(id -u)" -eq 0 ]; then
    chgrp nogroup "$root/usr/bin/hal-host"
    chown -R nobody:nogroup "$work"
    chmod 700 "$work/run"
    as_user=(setpriv --reuid=nobody --regid=nogroup --clear-groups)
fi
(cd "$work" && "${as_user[@]}" env -i PATH=/usr/bin:/bin HOME="$work" \
    XDG_RUNTIME_DIR="$work/run" HAL_INSTANCE=deb-ci-$$ \
    "$root/usr/bin/halrun" -f mill.hal) | tee "$work/run.log"
grep -q 'max following error' "$work/run.log" || fail "the main job did not finish"
[ -s "$work/pocket.png" ] || fail "the main job wrote no plot"
echo "main job from the package as $("${as_user[@]}" id -un): ok"
