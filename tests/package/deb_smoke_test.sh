#!/usr/bin/env bash
# The Debian packages on a machine that has nothing else (docs/packaging.md):
#   ../shared/tools/fresh-machine.sh 'bash tests/package/deb_smoke_test.sh DEB_DIR'
# installs DEB_DIR/*.deb with apt, runs the demo, imports the module and runs a README
# example with it, and builds the C++ sample against the installed library.
set -euo pipefail
debs=$(cd "${1:?usage: deb_smoke_test.sh DEB_DIR}" && pwd)
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq "$debs"/*.deb > /dev/null
echo "deb_smoke_test: installed $(cd "$debs" && ls *.deb | tr '\n' ' ')"
work=$(mktemp -d)
multicage demo -o "$work/demo" --backend cpu
test -s "$work/demo/side_by_side.png"
python3 -c "import multicage, sys; print('deb_smoke_test: import multicage from', multicage.__file__)"
cd /usr/share/multicage
python3 - <<'PY'
import cv2, multicage as mc
image = cv2.imread("samples/data/butterfly.jpg")
cage = mc.Multicage.load("samples/butterfly.yml")
out = mc.Deformer(image, cage, backend="cpu").deform(cage.pose("flap").vertices)
assert out.shape == image.shape and (out != image).any()
print("deb_smoke_test: a README example ran from /usr/share/multicage")
PY
apt-get install -y -qq --no-install-recommends g++ cmake make > /dev/null
cmake -S /usr/share/multicage/samples/cpp -B "$work/sample" > /dev/null
cmake --build "$work/sample" > /dev/null
"$work"/sample/deform_example /usr/share/multicage/samples/data/butterfly.jpg "$work/sample_out.png"
test -s "$work/sample_out.png"
echo "deb_smoke_test: OK"
