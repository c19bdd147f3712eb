#pragma once
#include <rclcpp/rclcpp.hpp>
#include <sensor_msgs/msg/imu.hpp>
#include <geometry_msgs/msg/twist.hpp>
#include "ros2_cpp/srv/set_mode.hpp"

namespace ros2_cpp
{
class Driver : public rclcpp::Node
{
public:
  explicit Driver(const rclcpp::NodeOptions & options);
  using Twist = geometry_msgs::msg::Twist;

private:
  void onCmd(const Twist::SharedPtr msg);
  void onMode(const std::shared_ptr<rmw_request_id_t> header,
              const std::shared_ptr<srv::SetMode::Request> request,
              std::shared_ptr<srv::SetMode::Response> response);
  rclcpp::Publisher<sensor_msgs::msg::Imu>::SharedPtr imu_pub_;
  rclcpp::Subscription<Twist>::SharedPtr cmd_sub_;
  rclcpp::Service<srv::SetMode>::SharedPtr mode_srv_;
  std::string frame_;
  static constexpr const char * kImuTopic = "imu/data_raw";
};
}  // namespace ros2_cpp
