#!/usr/bin/env bash
# Builds the Debian package from the binaries `cargo test --workspace`
# built (debug profile: this checks the package, it is not a release),
# lists and checks its contents, then unpacks it into a throw-away root
# where an unprivileged user runs the README's main job (the simulated
# mill) with the packaged binaries. Run from the workspace root by
# .ci/run; cargo-deb is installed if missing (about 2 minutes of CPU).
set -euo pipefail
cd "$(dirname "$0")/../.."

packaging/deb/install-cargo-deb

out=target/debian-ci
rm -rf "$out"
mkdir -p "$out"
cargo deb -p hal-tools --profile dev --no-build --fast -o "$out/" 2>&1 \
    | grep -v -e 'dev profile is not supported' -e 'To enable debug symbols' \
        -e "Only source paths starting with exactly 'target/release/'" || true
deb=$(ls "$out"/hal-suite_*.deb)
echo "package: $deb"

fail() { echo "package check: $*" >&2; exit 1; }

# The names of a control field's relations, one a line ("libc6 (>= 2.35)"
# gives libc6).
relation_names() {
    grep -m1 "^$1:" "$2" | cut -d: -f2- | tr ',' '\n' | sed -E 's/^ *([^ (]+).*/\1/' | grep -v '^$'
}

# The control file: each package once in Depends, every library the
# binaries need (dpkg-shlibdeps over all of them together) at the version
# they need, and the conflict with LinuxCNC's binaries declared.
check_control() {
    local control=$1 deb=$2 dup
    dup=$(relation_names Depends "$control" | sort | uniq -d)
    [ -z "$dup" ] || fail "Depends lists $dup more than once: $(grep '^Depends:' "$control")"
    local scratch
    scratch=$(mktemp -d)
    dpkg-deb -x "$deb" "$scratch/root"
    mkdir "$scratch/debian"
    printf 'Source: hal-suite\n\nPackage: hal-suite\nArchitecture: any\n' >"$scratch/debian/control"
    local needed
    needed=$(cd "$scratch" && dpkg-shlibdeps -O root/usr/bin/* 2>/dev/null | sed 's/^shlibs:Depends=//')
    rm -rf "$scratch"
    [ -n "$needed" ] || fail "dpkg-shlibdeps found nothing"
    local depends
    depends=$(grep -m1 '^Depends:' "$control" | cut -d: -f2-)
    local rel pkg ver have
    while read -r rel; do
        pkg=$(sed -E 's/^ *([^ (]+).*/\1/' <<<"$rel")
        ver=$(sed -nE 's/.*\(>= *([^)]+)\).*/\1/p' <<<"$rel")
        have=$(tr ',' '\n' <<<"$depends" | grep -E "^ *$pkg( |$)" || true)
        [ -n "$have" ] || fail "Depends lacks $rel (the binaries need it)"
        if [ -n "$ver" ]; then
            local declared
            declared=$(sed -nE 's/.*\(>= *([^)]+)\).*/\1/p' <<<"$have")
            [ -n "$declared" ] && dpkg --compare-versions "$declared" ge "$ver" \
                || fail "Depends has '$have', the binaries need $rel"
        fi
    done < <(tr ',' '\n' <<<"$needed")
    for other in linuxcnc-uspace linuxcnc; do
        relation_names Conflicts "$control" | grep -qx "$other" || fail "no Conflicts with $other"
        relation_names Replaces "$control" | grep -qx "$other" || fail "no Replaces of $other"
    done
}

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
# The Python module, prebuilt: in Debian's python3 path and as a wheel.
has usr/lib/python3/dist-packages/hal/__init__.py
has usr/lib/python3/dist-packages/hal/_hal.abi3.so
has usr/lib/python3/dist-packages/hal/query.py
has usr/lib/python3/dist-packages/pyhal/__init__.py
has usr/lib/python3/dist-packages/linuxcnc/__init__.py
has usr/lib/python3/dist-packages/linuxcnc/_stat.py
grep -q -E '[[:space:]]\./usr/share/hal-suite/python/hal-[^/]*-abi3-[^/]*\.whl$' <<<"$listing" \
    || fail "missing the Python wheel under usr/share/hal-suite/python"
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
check_control "$ctrl/control" "$deb"
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

# The Python module from the package, with nothing compiled: a component
# written in Python runs under the packaged halrun with the unpacked
# module, and the shipped wheel installs into a fresh virtual environment
# offline.
cat >"$work/pycheck.py" <<'PY'
import hal
comp = hal.component("pycheck")
comp.newpin("out", hal.HAL_FLOAT, hal.HAL_OUT)
comp["out"] = 2.5
comp.ready()
import time
try:
    while True:
        time.sleep(0.1)
except KeyboardInterrupt:
    pass
PY
cat >"$work/pycheck.hal" <<'HAL'
loadusr -Wn pycheck python3 pycheck.py
show pin pycheck
HAL
[ "$(id -u)" -eq 0 ] && chown nobody:nogroup "$work/pycheck.py" "$work/pycheck.hal"
(cd "$work" && "${as_user[@]}" env -i PATH=/usr/bin:/bin HOME="$work" \
    XDG_RUNTIME_DIR="$work/run" HAL_INSTANCE=deb-py-$$ \
    PYTHONPATH="$root/usr/lib/python3/dist-packages" \
    timeout 60 "$root/usr/bin/halrun" -f pycheck.hal) | tee "$work/py.log"
grep -q -E 'float +OUT +2\.5 +pycheck\.out' "$work/py.log" \
    || fail "a Python component did not run with the packaged module"
python3 -m venv "$root/venv"
"$root/venv/bin/pip" install -q --no-index "$root"/usr/share/hal-suite/python/hal-*.whl
"$root/venv/bin/python" -c 'import hal; assert hal.HAL_FLOAT is not None' \
    || fail "the packaged wheel does not import"
echo "Python module from the package (unpacked and as a wheel): ok"
