#include <ros/ros.h>
#include <actionlib/server/simple_action_server.h>
#include <actionlib/client/simple_action_client.h>
#include <ros1_cpp/DockAction.h>
#include <move_base_msgs/MoveBaseAction.h>

typedef actionlib::SimpleActionClient<move_base_msgs::MoveBaseAction> MoveBaseClient;

class DockServer
{
public:
  DockServer(const std::string& name)
  : as_(nh_, name, boost::bind(&DockServer::execute, this, _1), false)
  {
    as_.start();
  }
  void execute(const ros1_cpp::DockGoalConstPtr& goal) {}

private:
  ros::NodeHandle nh_;
  actionlib::SimpleActionServer<ros1_cpp::DockAction> as_;
};

int main(int argc, char** argv)
{
  ros::init(argc, argv, "dock_server");
  DockServer server("dock");
  MoveBaseClient ac("move_base", true);
  return 0;
}
