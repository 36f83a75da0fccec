# Every dependency is a Debian 12 package installed by scripts/setup. Several of Debian's CMake
# configs (OpenSubdiv, NIFTI, Teem) point at files that do not exist, so those are found by hand.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)
find_package(TBB REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3 REQUIRED)
find_package(OpenMesh REQUIRED)
find_package(glfw3 3.3 REQUIRED)
pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)

function(isoatlas_find_library target)
  cmake_parse_arguments(ARG "" "HEADER;INCLUDE_DIR" "NAMES;LINK" ${ARGN})
  add_library(${target} INTERFACE IMPORTED GLOBAL)
  foreach(name IN LISTS ARG_NAMES)
    find_library(ISOATLAS_LIB_${name} ${name} REQUIRED)
    target_link_libraries(${target} INTERFACE ${ISOATLAS_LIB_${name}})
  endforeach()
  find_path(ISOATLAS_INC_${target} ${ARG_HEADER} REQUIRED)
  target_include_directories(${target} SYSTEM INTERFACE ${ISOATLAS_INC_${target}} ${ARG_INCLUDE_DIR})
  target_link_libraries(${target} INTERFACE ${ARG_LINK})
endfunction()

# nifticlib 3: libnifti2 reads NIfTI-1 and NIfTI-2 alike.
isoatlas_find_library(isoatlas::nifti NAMES nifti2 znz HEADER nifti/nifti2_io.h
                      INCLUDE_DIR /usr/include/nifti LINK ZLIB::ZLIB m)
# libgiftiio 1.0 (GIfTI surfaces out, core/mesh_gifti.cpp only): its header includes nifti1_io.h.
isoatlas_find_library(isoatlas::gifti NAMES giftiio HEADER gifti/gifti_io.h INCLUDE_DIR /usr/include/gifti LINK isoatlas::nifti)
# GDCM 3.0 (DICOM series in, core/volume_dicom.cpp only).
isoatlas_find_library(isoatlas::gdcm NAMES gdcmMSFF gdcmDSED gdcmCommon HEADER gdcm-3.0/gdcmImageReader.h INCLUDE_DIR /usr/include/gdcm-3.0)
isoatlas_find_library(isoatlas::teem NAMES teem HEADER teem/nrrd.h LINK ZLIB::ZLIB m)
isoatlas_find_library(isoatlas::stb NAMES stb HEADER stb/stb_image_write.h)
# OpenSubdiv 3.5: Far (in osdCPU) and Osd's GLSL patch shader sources (osdGPU); viewer/smooth_render only.
isoatlas_find_library(isoatlas::opensubdiv NAMES osdGPU osdCPU HEADER opensubdiv/version.h)

# OpenMesh's config exports OpenMeshCore; make sure its headers are treated as system headers.
add_library(isoatlas::openmesh INTERFACE IMPORTED GLOBAL)
target_link_libraries(isoatlas::openmesh INTERFACE OpenMeshCore)
get_target_property(_om_inc OpenMeshCore INTERFACE_INCLUDE_DIRECTORIES)
if(_om_inc)
  target_include_directories(isoatlas::openmesh SYSTEM INTERFACE ${_om_inc})
endif()
target_compile_definitions(isoatlas::openmesh INTERFACE _USE_MATH_DEFINES)

find_package(GTest REQUIRED)

# CGAL (header-only): core/distance, multires' exact predicates and the multires bench; Eigen first, for Eigen3::Eigen.
# Last: CGAL's config puts its own Find modules (OpenMesh's among them) on the module path.
find_package(Eigen3 3.3 NO_MODULE)
find_package(CGAL REQUIRED)
