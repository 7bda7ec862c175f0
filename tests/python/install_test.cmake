# Script for Python.InstalledModuleImports: the module as users get it from `cmake --install`.
include(${CMAKE_CURRENT_LIST_DIR}/../common/install_to_scratch.cmake)
set(site ${prefix}/${PYDIR})
foreach(f ${PYDIR}/multicage/__init__.py ${DATADIR}/multicage/samples/python/augment.py)
    if(NOT EXISTS ${prefix}/${f})
        message(FATAL_ERROR "the install lacks ${f}")
    endif()
endforeach()
# Only the prefix on the path: the package and libmulticage (through the RPATH) must both
# come from the prefix, not from the build tree.
set(check [=[
import os, sys, numpy as np, multicage as mc
prefix = os.path.realpath(sys.argv[1])
mod = os.path.realpath(mc._multicage.__file__)
assert mod.startswith(prefix + os.sep), "the extension came from " + mod
libs = [l.split()[-1] for l in open("/proc/self/maps") if "libmulticage.so" in l]
assert libs and all(os.path.realpath(l).startswith(prefix + os.sep) for l in libs), libs
cage = mc.Multicage((64, 48))
cage.add_polygon(np.array([[10, 10], [50, 12], [48, 40], [12, 36]], np.float32))
cage.orient()
ok, why = cage.validate()
assert ok, why
image = np.arange(64 * 48, dtype=np.uint8).reshape(48, 64)
out = mc.deform_image(image, cage, cage.rest_pose(), backend="cpu")
assert out.shape == image.shape and out.dtype == image.dtype
print("imported", mod, "with", libs[0])
]=])
file(WRITE ${WORK_DIR}/check.py "${check}")
run(${CMAKE_COMMAND} -E env --unset=PYTHONPATH PYTHONPATH=${site} PYTHONNOUSERSITE=1
    ${PYTHON} ${WORK_DIR}/check.py ${prefix})
# The installed sample runs from the prefix too.
set(sample ${prefix}/${DATADIR}/multicage/samples/python/augment.py)
run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} PYTHONNOUSERSITE=1 ${PYTHON} ${sample} --help)
run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} PYTHONNOUSERSITE=1 ${PYTHON} ${sample}
    ${SOURCE_DIR}/samples/data/HappyFish.jpg -o ${WORK_DIR}/augmented -n 2 --seed 1 --backend cpu)
if(NOT EXISTS ${WORK_DIR}/augmented/HappyFish_001.png OR NOT EXISTS ${WORK_DIR}/augmented/HappyFish_001_mask.png)
    message(FATAL_ERROR "the installed sample wrote no images into ${WORK_DIR}/augmented")
endif()
# Issue 40 item 2: the README's Python examples run as written from <prefix>/share/multicage,
# with the installed module and the installed samples only.
foreach(f samples/butterfly.yml samples/butterfly_flap.yml samples/data/butterfly.jpg
        samples/python/train_loop.py samples/python/bench_batch.py samples/cpp/deform_example.cpp)
    if(NOT EXISTS ${prefix}/${DATADIR}/multicage/${f})
        message(FATAL_ERROR "the install lacks ${DATADIR}/multicage/${f}")
    endif()
endforeach()
run(${CMAKE_COMMAND} -E env PYTHONPATH=${site}:${SOURCE_DIR}/tests/python PYTHONNOUSERSITE=1
    MULTICAGE_SOURCE_DIR=${SOURCE_DIR} MULTICAGE_README_CWD=${prefix}/${DATADIR}/multicage
    PYTHONDONTWRITEBYTECODE=1
    ${PYTHON} -m pytest -q -p no:cacheprovider ${SOURCE_DIR}/tests/python/test_readme.py
    -k "readme_python_block")
message(STATUS "installed Python module OK")
