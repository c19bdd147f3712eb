#include <ros/ros.h>
#include <std_msgs/String.h>
#include <sensor_msgs/LaserScan.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <boost/bind/bind.hpp>

void chatterCallback(const std_msgs::String::ConstPtr& msg) {}

class Listener
{
public:
  explicit Listener(ros::NodeHandle nh) : nh_(nh)
  {
    scan_sub_ = nh_.subscribe("scan", 5, &Listener::scanCallback, this);                 // member function
    cmd_sub_ = nh_.subscribe("cmd_vel", 1, boost::bind(&Listener::cmdCallback, this, boost::placeholders::_1, 7));
    odom_sub_ = nh_.subscribe<nav_msgs::Odometry>("odom", 1, [](const nav_msgs::Odometry::ConstPtr& o) {});
  }
  void scanCallback(const sensor_msgs::LaserScanConstPtr& scan);
  void cmdCallback(const geometry_msgs::Twist& cmd, int id);

private:
  ros::NodeHandle nh_;
  ros::Subscriber scan_sub_, cmd_sub_, odom_sub_;
};

void Listener::scanCallback(const sensor_msgs::LaserScanConstPtr& scan) {}
void Listener::cmdCallback(const geometry_msgs::Twist& cmd, int id) {}

int main(int argc, char** argv)
{
  ros::init(argc, argv, "listener");
  ros::NodeHandle n;
  ros::Subscriber sub = n.subscribe("chatter", 1000, chatterCallback);   // type from the callback
  Listener l(n);
  ros::spin();
  return 0;
}
