# SPDX-License-Identifier: Apache-2.0
#
# Locates the system OpenVDB (Debian: libopenvdb-dev, plus the Boost headers its
# io/ headers include) for tests/compat and bench/, the only code that links it.
# Defines the imported target OpenVDB::openvdb and sets VDB_OPENVDB_FOUND and
# VDB_OPENVDB_VERSION. Debian ships only OpenVDB's FindOpenVDB.cmake, which also
# searches for Python, Boost libraries and more; the few lookups below suffice.

include_guard(GLOBAL)

set(VDB_OPENVDB_FOUND FALSE)
set(VDB_OPENVDB_VERSION "")

if(TARGET OpenVDB::openvdb)
    set(VDB_OPENVDB_FOUND TRUE)
    return()
endif()

find_path(VDB_OPENVDB_INCLUDE_DIR openvdb/openvdb.h)
find_library(VDB_OPENVDB_LIBRARY openvdb)
find_library(VDB_IMATH_LIBRARY NAMES Imath Imath-3_1)
find_path(VDB_BOOST_INCLUDE_DIR boost/uuid/uuid.hpp)
mark_as_advanced(VDB_OPENVDB_INCLUDE_DIR VDB_OPENVDB_LIBRARY VDB_IMATH_LIBRARY
                 VDB_BOOST_INCLUDE_DIR)

if(VDB_OPENVDB_INCLUDE_DIR AND VDB_OPENVDB_LIBRARY AND VDB_IMATH_LIBRARY
   AND VDB_BOOST_INCLUDE_DIR AND TARGET TBB::tbb)
    file(STRINGS "${VDB_OPENVDB_INCLUDE_DIR}/openvdb/version.h" _vdb_ov_version
         REGEX "^#define OPENVDB_LIBRARY_VERSION_STRING ")
    string(REGEX REPLACE ".*\"(.*)\".*" "\\1" VDB_OPENVDB_VERSION "${_vdb_ov_version}")

    add_library(OpenVDB::openvdb UNKNOWN IMPORTED)
    set_target_properties(OpenVDB::openvdb PROPERTIES
        IMPORTED_LOCATION "${VDB_OPENVDB_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${VDB_OPENVDB_INCLUDE_DIR};${VDB_BOOST_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES "TBB::tbb;${VDB_IMATH_LIBRARY}")
    set(VDB_OPENVDB_FOUND TRUE)
    message(STATUS "OpenVDB ${VDB_OPENVDB_VERSION}: ${VDB_OPENVDB_LIBRARY}")
else()
    message(STATUS "OpenVDB not found (tests/compat and bench/ need libopenvdb-dev "
                   "and the Boost headers)")
endif()
