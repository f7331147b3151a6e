# grip_mujoco_from_dir(<dir>): makes the imported target mujoco::mujoco (and sets mujoco_VERSION)
# from a MuJoCo that ships no CMake package: a directory holding include/mujoco/mujoco.h and the
# shared library, either beside include/ (the PyPI `mujoco` package's directory, printed by
#   python -c "import mujoco, os; print(os.path.dirname(mujoco.__file__))")
# or under lib/ (a release archive's root, or an install prefix).
# It does nothing if mujoco::mujoco exists already, and stops with an error naming what is
# missing if the directory does not hold a MuJoCo.
function(grip_mujoco_from_dir dir)
  if(TARGET mujoco::mujoco)
    return()
  endif()
  set(header "${dir}/include/mujoco/mujoco.h")
  if(NOT EXISTS "${header}")
    message(FATAL_ERROR "GRIP_MUJOCO_DIR=${dir}: no include/mujoco/mujoco.h there")
  endif()
  # The shared library: libmujoco.so (or a versioned libmujoco.so.X.Y.Z, as PyPI ships it),
  # libmujoco.dylib or mujoco.lib, beside include/ or under lib/.
  file(GLOB candidates LIST_DIRECTORIES false
       "${dir}/libmujoco.so" "${dir}/libmujoco.so.*" "${dir}/lib/libmujoco.so" "${dir}/lib/libmujoco.so.*"
       "${dir}/libmujoco*.dylib" "${dir}/lib/libmujoco*.dylib" "${dir}/lib/mujoco.lib")
  if(NOT candidates)
    message(FATAL_ERROR "GRIP_MUJOCO_DIR=${dir}: no MuJoCo library (libmujoco.so*, .dylib or lib/mujoco.lib) there")
  endif()
  list(SORT candidates)
  list(GET candidates 0 library)
  # mjVERSION_HEADER: 222 for 2.2.2 (before 3.0), 3002000 or 4000001 for 3.2.0 or 4.0.1.
  file(STRINGS "${header}" version_line REGEX "^#define mjVERSION_HEADER [0-9]+")
  string(REGEX REPLACE "^#define mjVERSION_HEADER ([0-9]+).*" "\\1" v "${version_line}")
  if(v GREATER_EQUAL 1000000)
    math(EXPR major "${v} / 1000000")
    math(EXPR minor "(${v} / 1000) % 1000")
    math(EXPR patch "${v} % 1000")
  else()
    math(EXPR major "${v} / 100")
    math(EXPR minor "(${v} / 10) % 10")
    math(EXPR patch "${v} % 10")
  endif()
  add_library(mujoco::mujoco SHARED IMPORTED GLOBAL)
  set_target_properties(mujoco::mujoco PROPERTIES IMPORTED_LOCATION "${library}"
                                                  INTERFACE_INCLUDE_DIRECTORIES "${dir}/include")
  if(library MATCHES "\\.lib$")
    set_target_properties(mujoco::mujoco PROPERTIES IMPORTED_IMPLIB "${library}")
  endif()
  set(mujoco_VERSION "${major}.${minor}.${patch}" PARENT_SCOPE)
endfunction()
