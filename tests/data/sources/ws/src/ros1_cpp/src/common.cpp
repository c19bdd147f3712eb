#include <ros/ros.h>
#include <std_msgs/Empty.h>

void announce(ros::NodeHandle& nh)
{
  static ros::Publisher hello = nh.advertise<std_msgs::Empty>("hello", 1, true);
}
