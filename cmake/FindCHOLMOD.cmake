# FindCHOLMOD: SuiteSparse's CHOLMOD (Debian ships no CMake config for SuiteSparse 5.x).
# Defines SuiteSparse::CHOLMOD and CHOLMOD_FOUND.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
foreach(_lib amd camd colamd ccolamd metis)
  string(TOUPPER ${_lib} _LIB)
  find_library(${_LIB}_LIBRARY NAMES ${_lib} lib${_lib}.so.5)
endforeach()
# LAPACK: CHOLMOD's own dependency, which the condensation also calls (dlauum: S from the factor).
find_package(LAPACK QUIET)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS CHOLMOD_LIBRARY CHOLMOD_INCLUDE_DIR SUITESPARSE_CONFIG_LIBRARY
                                  LAPACK_FOUND)
if(CHOLMOD_FOUND AND NOT TARGET SuiteSparse::CHOLMOD)
  add_library(SuiteSparse::CHOLMOD UNKNOWN IMPORTED)
  set(_deps ${SUITESPARSE_CONFIG_LIBRARY} LAPACK::LAPACK)
  foreach(_L AMD CAMD COLAMD CCOLAMD)
    if(${_L}_LIBRARY)
      list(APPEND _deps ${${_L}_LIBRARY})
    endif()
  endforeach()
  set_target_properties(SuiteSparse::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${_deps}")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_LIBRARY SUITESPARSE_CONFIG_LIBRARY)
