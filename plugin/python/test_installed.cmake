# ctest python.installed: install the module into a scratch prefix and import it from
# there, with only that directory on PYTHONPATH and a working directory outside the build.
foreach(v CMAKE_COMMAND PYTHON BUILD_DIR PREFIX MODULE_DIR)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "test_installed.cmake: ${v} is not set")
  endif()
endforeach()
file(REMOVE_RECURSE ${PREFIX})
file(MAKE_DIRECTORY ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --component python --prefix ${PREFIX}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install --component python failed (${rc})")
endif()
set(site ${PREFIX}/${MODULE_DIR})
file(GLOB installed ${site}/obscura/_obscura*.so)
if(NOT installed)
  message(FATAL_ERROR "no obscura module under ${site}")
endif()
set(check [=[
import os, sys
import numpy as np
import obscura
site = os.path.realpath(sys.argv[1])
where = os.path.realpath(obscura.__file__)
assert where.startswith(site + os.sep), f"imported {where}, expected it under {site}"
cam = obscura.Camera.perspective(60.0, 16, 12, camera_to_world=np.eye(4))
depth = np.full((12, 16), 5.0, np.float32)
normal = np.zeros((12, 16, 3), np.float32)
normal[..., 2] = 1.0
ao = obscura.compute_ao(depth, normal, camera=cam, radius=0.5)
assert ao.shape == (12, 16) and ao.dtype == np.float32, (ao.shape, ao.dtype)
assert abs(float(ao.min()) - 1.0) < 1e-5, ao.min()
import obscura.farm
assert callable(obscura.farm.run_dask)
print("installed obscura", obscura.__version__, "from", where)
]=])
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=PYTHONHOME --unset=PYTHONSTARTUP PYTHONPATH=${site}
                        PYTHONNOUSERSITE=1 PYTHONDONTWRITEBYTECODE=1
                        ${PYTHON} -c "${check}" ${site}
                WORKING_DIRECTORY ${PREFIX} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "importing the installed module failed (${rc})")
endif()
