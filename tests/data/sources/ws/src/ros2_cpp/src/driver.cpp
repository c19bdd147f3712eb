#include "ros2_cpp/driver.hpp"
#include "rclcpp_components/register_node_macro.hpp"
#include <std_srvs/srv/trigger.hpp>

namespace ros2_cpp
{
Driver::Driver(const rclcpp::NodeOptions & options)
: Node("driver", options)
{
  frame_ = declare_parameter<std::string>("frame_id", "imu_link");
  double rate = this->declare_parameter("rate", 50.0);
  imu_pub_ = create_publisher<sensor_msgs::msg::Imu>(kImuTopic, rclcpp::SensorDataQoS());
  cmd_sub_ = this->create_subscription<Twist>(
    "cmd_vel", 10, std::bind(&Driver::onCmd, this, std::placeholders::_1));
  mode_srv_ = create_service<srv::SetMode>(
    "~/set_mode", std::bind(&Driver::onMode, this, std::placeholders::_1, std::placeholders::_2,
    std::placeholders::_3));
  auto reset = create_client<std_srvs::srv::Trigger>("/reset");
  bool verbose = false;
  get_parameter("verbose", verbose);
  set_parameter(rclcpp::Parameter("started", true));
}

void Driver::onCmd(const Twist::SharedPtr msg) {}
void Driver::onMode(const std::shared_ptr<rmw_request_id_t>, const std::shared_ptr<srv::SetMode::Request>,
                    std::shared_ptr<srv::SetMode::Response>) {}
}  // namespace ros2_cpp

RCLCPP_COMPONENTS_REGISTER_NODE(ros2_cpp::Driver)
