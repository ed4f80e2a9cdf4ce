#!/usr/bin/env bash
# Checks hal-suite-linuxcnc-modules: builds it (dev profile), checks its
# contents and control file, then installs it with dpkg beside Debian 12's
# linuxcnc-uspace in a throw-away root, has LinuxCNC's own halrun load one
# of the modules from there, removes the package and checks that
# LinuxCNC's own files are back. Run from the workspace root by
# scripts/test-all.
#
# Needs the LinuxCNC peer's packages (scripts/linuxcnc-peer install);
# loading a module in LinuxCNC needs root (a private mount namespace).
# Whatever cannot run here is said, and the script then ends with status
# 77 (skipped in part), never 0.
set -euo pipefail
cd "$(dirname "$0")/../.."

fail() { echo -e "module package check: $*" >&2; exit 1; }
skipped=""

# The modules `cargo test --workspace` built (no second cargo run).
deb=$(packaging/linuxcnc-modules/build-deb --profile dev --no-build target/debian-modules-ci | tail -1)
echo "package: $deb"
package=hal-suite-linuxcnc-modules
moddir=usr/lib/linuxcnc/modules

# --- contents and control file
listing=$(dpkg-deb -c "$deb")
for dir in linuxcnc-modules/*/; do
    name=$(basename "$dir")
    [ "$name" = tests ] && continue
    grep -q -E "[[:space:]]\./$moddir/$name\.so\$" <<<"$listing" || fail "missing $moddir/$name.so"
done
if awk '{print $1}' <<<"$listing" | grep -q '[sS]'; then
    fail "a file has a setuid or setgid bit"
fi
ctrl=$(mktemp -d)
root=$(mktemp -d)
trap 'rm -rf "$ctrl" "$root"' EXIT
dpkg-deb -e "$deb" "$ctrl"
grep -q -E '^Depends:.*linuxcnc-uspace' "$ctrl/control" || fail "does not depend on linuxcnc-uspace"
grep -q -E '^(Conflicts|Replaces|Breaks):' "$ctrl/control" && fail "declares a conflict: $(grep -E '^(Conflicts|Replaces|Breaks):' "$ctrl/control")"
diverted=$(sed -n 's/^ *for m in \(.*\); do$/\1/p' "$ctrl/preinst" | head -1)
[ -n "$diverted" ] || fail "the preinst diverts nothing"
grep -q "dpkg-divert --package $package --remove" "$ctrl/postrm" || fail "the postrm gives no diversion back"
echo "package contents: ok (diverted: $diverted)"

# --- LinuxCNC's package
if ! debs=$(scripts/linuxcnc-peer debs 2>/dev/null); then
    echo "module package check: LinuxCNC's packages are not here (scripts/linuxcnc-peer install failed?):"
    echo "  installing beside linuxcnc-uspace SKIPPED"
    exit 77
fi
lcnc=$(ls "$debs"/linuxcnc-uspace_*.deb)
# Every module both packages have must be diverted, and only those.
theirs=$(dpkg-deb -c "$lcnc" | sed -n "s|.*[[:space:]]\./$moddir/\([^/]*\)\.so\$|\1|p" | sort)
ours=$(sed -n "s|.*[[:space:]]\./$moddir/\([^/]*\)\.so\$|\1|p" <<<"$listing" | sort)
both=$(comm -12 <(echo "$theirs") <(echo "$ours") | tr '\n' ' ' | sed 's/ $//')
[ "$both" = "$(tr ' ' '\n' <<<"$diverted" | sort | tr '\n' ' ' | sed 's/ $//')" ] \
    || fail "LinuxCNC ships '$both' of our modules, the preinst diverts '$diverted'"

# --- the throw-away root: LinuxCNC's packages installed with dpkg, then
# ours (its preinst runs dpkg-divert inside the root). The maintainer
# scripts run outside a chroot (DPKG_ROOT set); linuxcnc-uspace's postinst
# byte-compiles its Python with py3compile, which would compile the host's
# files instead, so a py3compile that does nothing comes first on PATH.
# Only the libraries of the image itself are missing from the root, hence
# --force-depends.
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$ctrl/shim"
touch "$root/var/lib/dpkg/status"
for tool in py3compile pypy3compile; do
    printf '#!/bin/sh\nexit 0\n' >"$ctrl/shim/$tool"
    chmod 0755 "$ctrl/shim/$tool"
done
opts=(--root="$root" --force-not-root --force-script-chrootless --force-depends)
PATH="$ctrl/shim:$PATH" dpkg "${opts[@]}" -i "$debs"/*.deb >/dev/null 2>"$ctrl/dpkg.log" \
    || fail "installing LinuxCNC's packages in the root failed:\n$(cat "$ctrl/dpkg.log")"
cp "$root/$moddir/hal_parport.so" "$ctrl/theirs-hal_parport.so"
dpkg "${opts[@]}" -i "$deb" >/dev/null 2>"$ctrl/dpkg.log" \
    || fail "installing the package failed:\n$(cat "$ctrl/dpkg.log")"
dpkg --root="$root" -s "$package" | grep -q '^Status: install ok installed' || fail "not installed"
for m in $diverted; do
    [ -f "$root/$moddir/$m.so.linuxcnc-uspace" ] || fail "LinuxCNC's $m.so was not kept aside"
done
dpkg-deb --fsys-tarfile "$deb" | tar -xO "./$moddir/hal_parport.so" | cmp -s - "$root/$moddir/hal_parport.so" \
    || fail "hal_parport.so in the root is not ours"
cmp -s "$ctrl/theirs-hal_parport.so" "$root/$moddir/hal_parport.so.linuxcnc-uspace" \
    || fail "the kept-aside hal_parport.so is not LinuxCNC's"
echo "installed beside linuxcnc-uspace: ok"

# --- LinuxCNC's halrun loads our module from the root
if [ "$(id -u)" -ne 0 ]; then
    echo "module package check: loading a module in LinuxCNC needs root (a private mount namespace): SKIPPED"
    skipped=1
else
    cat >"$ctrl/load.hal" <<'HAL'
loadrt canservo backend=sim nodes=3 diag_ms=0
show pin canservo.0.enable
show funct canservo.read
loadrt hal_parport cfg="0 sim"
show pin parport.0.pin-01-out
HAL
    chmod 0644 "$ctrl/load.hal"
    chmod 0755 "$ctrl"
    out=$(LINUXCNC_PEER_PREFIX="$root" scripts/linuxcnc-peer run halrun -s -k -f "$ctrl/load.hal" 2>&1) \
        || fail "LinuxCNC's halrun failed:\n$out"
    grep -q -E 'bit +IN +FALSE +canservo\.0\.enable' <<<"$out" || fail "no canservo pins in LinuxCNC:\n$out"
    grep -q "canservo.read" <<<"$out" || fail "no canservo function in LinuxCNC:\n$out"
    # LinuxCNC's own hal_parport has no simulated port: this one is ours.
    grep -q -E 'bit +IN +FALSE +parport\.0\.pin-01-out' <<<"$out" \
        || fail "our hal_parport (diverted over LinuxCNC's) did not load:\n$out"
    echo "LinuxCNC's halrun loads canservo and (in place of its own) hal_parport from the package: ok"
fi

# --- removal gives LinuxCNC's files back
dpkg "${opts[@]}" -r "$package" >/dev/null 2>"$ctrl/dpkg.log" \
    || fail "removing the package failed:\n$(cat "$ctrl/dpkg.log")"
cmp -s "$ctrl/theirs-hal_parport.so" "$root/$moddir/hal_parport.so" \
    || fail "removing the package did not give LinuxCNC's hal_parport.so back"
for m in $diverted; do
    [ ! -e "$root/$moddir/$m.so.linuxcnc-uspace" ] || fail "$m.so.linuxcnc-uspace left behind"
done
echo "removed, LinuxCNC's modules back: ok"
[ -z "$skipped" ] || exit 77
