# marvin_add_skill(<target> SOURCES <files>... MANIFEST <skill.json> [OUTPUT_DIR <dir>])
#
# Builds a native Marvin skill: a shared library loaded with dlopen() that exports only
# marvin_get_skill_descriptor() (see marvin/skill.hpp). The skill's folder, ready for a
# skills directory, is <dir>/<id>/ holding skill.json and the library named by its
# "entry" (default skill.so). <dir> defaults to ${MARVIN_SKILLS_OUTPUT_DIR} if set, else
# ${CMAKE_BINARY_DIR}/skills. The target property MARVIN_SKILL_DIR holds the folder.
function(marvin_add_skill target)
  cmake_parse_arguments(ARG "" "MANIFEST;OUTPUT_DIR" "SOURCES" ${ARGN})
  if(NOT ARG_MANIFEST)
    message(FATAL_ERROR "marvin_add_skill(${target}): MANIFEST skill.json is required")
  endif()
  get_filename_component(manifest ${ARG_MANIFEST} ABSOLUTE)
  file(READ ${manifest} manifest_text)
  string(JSON skill_id ERROR_VARIABLE json_error GET "${manifest_text}" id)
  if(json_error)
    message(FATAL_ERROR "marvin_add_skill(${target}): ${manifest}: cannot read \"id\": ${json_error}")
  endif()
  string(JSON entry ERROR_VARIABLE no_entry GET "${manifest_text}" entry)
  if(no_entry)
    set(entry skill.so)
  endif()
  if(NOT ARG_OUTPUT_DIR)
    if(MARVIN_SKILLS_OUTPUT_DIR)
      set(ARG_OUTPUT_DIR ${MARVIN_SKILLS_OUTPUT_DIR})
    else()
      set(ARG_OUTPUT_DIR ${CMAKE_BINARY_DIR}/skills)
    endif()
  endif()
  set(skill_dir ${ARG_OUTPUT_DIR}/${skill_id})
  get_filename_component(entry_name ${entry} NAME_WE)
  get_filename_component(entry_ext ${entry} LAST_EXT)

  add_library(${target} MODULE ${ARG_SOURCES})
  if(TARGET marvin_sdk)
    target_link_libraries(${target} PRIVATE marvin_sdk)
  else()
    target_link_libraries(${target} PRIVATE MarvinSDK::sdk)
  endif()
  set_target_properties(${target} PROPERTIES
    PREFIX "" OUTPUT_NAME ${entry_name} SUFFIX "${entry_ext}"
    LIBRARY_OUTPUT_DIRECTORY ${skill_dir}
    CXX_VISIBILITY_PRESET hidden C_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON
    MARVIN_SKILL_DIR ${skill_dir})
  # Multi-config generators would add a per-config folder; keep the skill's folder flat.
  foreach(config ${CMAKE_CONFIGURATION_TYPES})
    string(TOUPPER ${config} config)
    set_target_properties(${target} PROPERTIES LIBRARY_OUTPUT_DIRECTORY_${config} ${skill_dir})
  endforeach()
  configure_file(${manifest} ${skill_dir}/skill.json COPYONLY)
  if(COMMAND marvin_target_defaults)
    marvin_target_defaults(${target})
  endif()
endfunction()
