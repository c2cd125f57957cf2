# Every third-party dependency, from Debian's packages (tools/dev.sh installs them).
# Each heavy dependency stays PRIVATE to the one stage that uses it.

# Debian's own interpreter (it has numpy, h5py, scipy from apt), not a pyenv shim first on PATH.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Debian's python3")
endif()
set(PYBIND11_FINDPYTHON ON)

find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(OpenSSL REQUIRED COMPONENTS Crypto)

# meshes: assimp, CGAL, qhull; hands: urdfdom, TinyXML (the MJCF reader; urdfdom parses with it too)
find_package(assimp REQUIRED)
find_package(CGAL REQUIRED)
find_package(urdfdom REQUIRED)
pkg_check_modules(TINYXML REQUIRED IMPORTED_TARGET tinyxml)
# grasp_sim: Debian's float64 Bullet. The pkg-config file carries -DBT_USE_DOUBLE_PRECISION,
# which the imported target passes to every file that includes Bullet.
pkg_check_modules(BULLET REQUIRED IMPORTED_TARGET bullet-float64)
# quality: reentrant qhull
pkg_check_modules(QHULL_R REQUIRED IMPORTED_TARGET qhull_r)
# mapstore: HDF5 C API
find_package(HDF5 REQUIRED COMPONENTS C)
# validate: MuJoCo 2.2.2 (libmujoco-dev)
find_package(mujoco REQUIRED)
# clustering / integration: FLANN (needs liblz4)
pkg_check_modules(LZ4 REQUIRED IMPORTED_TARGET liblz4)
find_package(flann REQUIRED)
# integration: glibc's vector math library (libmvec) for the mixture's exp, two lanes at a time;
# without it the scalar std::exp is used (same results within 4 ulp).
include(CheckCXXSourceCompiles)
set(CMAKE_REQUIRED_LIBRARIES mvec)
check_cxx_source_compiles([=[
#include <emmintrin.h>
extern "C" __m128d _ZGVbN2v_exp(__m128d);
int main() { double o[2]; _mm_storeu_pd(o, _ZGVbN2v_exp(_mm_set1_pd(1.0))); return o[0] > 2 ? 0 : 1; }
]=] TASKMAP_HAVE_LIBMVEC)
unset(CMAKE_REQUIRED_LIBRARIES)
find_package(nlohmann_json 3 REQUIRED)
find_package(CLI11 REQUIRED)
pkg_check_modules(CAIRO IMPORTED_TARGET cairo)

find_package(Python3 COMPONENTS Interpreter Development.Module)
if(TASKMAP_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(TASKMAP_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
if(TASKMAP_BUILD_PYTHON)
  find_package(pybind11 CONFIG REQUIRED)
endif()
# reaching tests only: independent oracles for kinematics (KDL) and capsule distances (FCL).
if(TASKMAP_BUILD_TESTS)
  pkg_check_modules(KDL QUIET IMPORTED_TARGET orocos-kdl)
  pkg_check_modules(FCL QUIET IMPORTED_TARGET fcl)
endif()
