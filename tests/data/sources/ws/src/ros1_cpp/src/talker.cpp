#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_msgs/Int32.h>
#include "ros1_cpp/constants.h"

using namespace ros1_cpp;

class Talker
{
public:
  Talker(ros::NodeHandle& nh)
  : nh_(nh), pnh_("~"), sub_nh_(nh, "arm"), topic_("chatter")
  {
    pub_ = nh_.advertise<std_msgs::String>(topic_, 10);               // a member set in the constructor
    status_ = nh_.advertise<Text>(STATUS_TOPIC, 1);                   // a #define, a typedef
    count_ = pnh_.advertise<Count>(kPrefix + "/count", 1);           // private, a constant + a literal
    joint_ = sub_nh_.advertise<std_msgs::Int32>("joint", 1);          // a child node handle: arm/joint
    std::string out;
    pnh_.param<std::string>("output", out, "out");
    dyn_ = nh_.advertise<std_msgs::String>(out, 1);                   // a parameter's value: dynamic
    pnh_.getParam("rate", rate_);
    nh_.setParam("/talker_ready", true);
    ros::param::set("last_talker", std::string("talker"));
    std::string found;
    nh_.searchParam("frame", found);
    nh_.deleteParam("stale");
    double gain = nh_.param("gain", 0.5);
  }

private:
  ros::NodeHandle nh_, pnh_, sub_nh_;
  std::string topic_;
  ros::Publisher pub_, status_, count_, joint_, dyn_;
  int rate_;
};

void announce(ros::NodeHandle& nh);
ros::Publisher agg(ros::NodeHandle& nh);

int main(int argc, char** argv)
{
  ros::init(argc, argv, "talker");
  ros::NodeHandle nh;
  Talker t(nh);
  announce(nh);
  ros::Publisher a = ros1_cpp::agg(nh);
  ros::spin();
  return 0;
}
