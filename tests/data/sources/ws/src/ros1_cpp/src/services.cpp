#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <ros1_cpp/Reset.h>

bool onReset(ros1_cpp::Reset::Request& req, ros1_cpp::Reset::Response& res) { return true; }

class Server
{
public:
  bool trigger(std_srvs::TriggerRequest& req, std_srvs::TriggerResponse& res) { return true; }
};

int main(int argc, char** argv)
{
  ros::init(argc, argv, "services");
  ros::NodeHandle nh;
  Server s;
  ros::ServiceServer a = nh.advertiseService("reset", onReset);
  ros::ServiceServer b = nh.advertiseService("trigger", &Server::trigger, &s);
  ros::ServiceClient c = nh.serviceClient<std_srvs::Trigger>("/other/trigger");
  std_srvs::Trigger t;
  ros::service::call("ping", t);
  return 0;
}
