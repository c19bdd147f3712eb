#include "ros1_cpp/constants.h"
#include <ros/ros.h>

namespace ros1_cpp {
ros::Publisher agg(ros::NodeHandle& nh)
{
  // the constant of the header, absolute
  return nh.advertise<Text>(kDiagnostics, 5);
}
}
