# StateBench::rosbag: Debian's ROS1 bag library (librosbag-storage-dev, rosbag_storage) with the
# message headers of libsensor-msgs-dev, libnav-msgs-dev, libgeometry-msgs-dev, libtf2-msgs-dev,
# as an imported target made by hand. Neither of Debian's own integrations works here:
# rosbag_storage.pc requires a pluginlib.pc that Debian does not ship, and the catkin CMake config
# (find_package(rosbag_storage)) loads ament_cmake, which runs Python helper scripts at configure
# time and fails outside a ROS environment. What a program needs is small and stable: the headers
# (in /usr/include, plus pluginlib and its ROS 2 dependencies in their own subfolders, which
# rosbag/bag.h includes) and five shared libraries.
#
# The ROS1 message headers do not compile as C++20 (they use std::allocator<T>::rebind, removed
# in C++20): the sources that include them are compiled as C++17 (statebench_ros1_sources).

find_path(ROSBAG_INCLUDE_DIR rosbag/bag.h)
find_path(ROS_SENSOR_MSGS_INCLUDE_DIR sensor_msgs/PointCloud2.h)
find_path(ROS_NAV_MSGS_INCLUDE_DIR nav_msgs/Odometry.h)
find_path(ROS_TF2_MSGS_INCLUDE_DIR tf2_msgs/TFMessage.h)
set(_statebench_ros_include_dirs "")
foreach(pkg pluginlib class_loader rcutils rcpputils ament_index_cpp)
  # ROS 2 layout: /usr/include/<pkg>/<pkg>/*.hpp, included as <pkg/...>.
  find_path(ROS_${pkg}_INCLUDE_DIR ${pkg} PATHS /usr/include/${pkg} NO_DEFAULT_PATH)
  if(ROS_${pkg}_INCLUDE_DIR)
    list(APPEND _statebench_ros_include_dirs ${ROS_${pkg}_INCLUDE_DIR})
  else()
    set(_statebench_ros_missing_header ${pkg})
  endif()
endforeach()
set(_statebench_ros_libraries "")
foreach(lib rosbag_storage roscpp_serialization rostime cpp_common console_bridge)
  find_library(ROS_${lib}_LIBRARY ${lib})
  if(NOT ROS_${lib}_LIBRARY)
    set(_statebench_ros_missing_lib ${lib})
  endif()
  list(APPEND _statebench_ros_libraries ${ROS_${lib}_LIBRARY})
endforeach()
if(NOT ROSBAG_INCLUDE_DIR OR NOT ROS_SENSOR_MSGS_INCLUDE_DIR OR NOT ROS_NAV_MSGS_INCLUDE_DIR OR
   NOT ROS_TF2_MSGS_INCLUDE_DIR OR _statebench_ros_missing_header OR _statebench_ros_missing_lib)
  message(FATAL_ERROR "ROS1 bag support needs librosbag-storage-dev libsensor-msgs-dev "
          "libnav-msgs-dev libgeometry-msgs-dev libtf2-msgs-dev (bash scripts/setup.sh); missing: "
          "${_statebench_ros_missing_header} ${_statebench_ros_missing_lib}")
endif()

if(NOT TARGET StateBench::rosbag)
  # GLOBAL: `sensors` links it privately, and every target that links `sensors` (a static
  # library) links it too, from other directories.
  add_library(StateBench::rosbag INTERFACE IMPORTED GLOBAL)
  # SYSTEM: warnings inside ROS headers are not ours.
  set_target_properties(StateBench::rosbag PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${_statebench_ros_include_dirs}"
    INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${_statebench_ros_include_dirs}"
    INTERFACE_LINK_LIBRARIES "${_statebench_ros_libraries}")
endif()

# statebench_ros1_sources(<source>...): sources that include ROS1 message headers compile as
# C++17 (the flag comes after the target's -std=c++20, so it wins with GCC and Clang).
function(statebench_ros1_sources)
  # Compiled on their own, outside any unity batch of the C++20 sources.
  set_source_files_properties(${ARGN} PROPERTIES COMPILE_OPTIONS "-std=c++17"
                                                 SKIP_UNITY_BUILD_INCLUSION ON)
endfunction()
