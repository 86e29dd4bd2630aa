# find_package(facet): the shader-plugin SDK.
# Gives the target facet::sdk (headers, C++20, GLM) and facet_add_shader().
include(CMakeFindDependencyMacro)
find_dependency(glm)
include("${CMAKE_CURRENT_LIST_DIR}/facetTargets.cmake")
include("${CMAKE_CURRENT_LIST_DIR}/FacetShader.cmake")
