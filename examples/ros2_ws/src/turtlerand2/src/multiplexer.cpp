// multiplexer in ROS 2 (the thesis's Listing 2.7, with rclcpp): forwards cmd_vel_high at once and
// holds cmd_vel_low for ten seconds after each high-priority message.
#include <chrono>
#include <memory>

#include "geometry_msgs/msg/twist.hpp"
#include "rclcpp/rclcpp.hpp"

using Twist = geometry_msgs::msg::Twist;
using namespace std::chrono_literals;

class Multiplexer : public rclcpp::Node
{
public:
  Multiplexer()
  : Node("multiplexer")
  {
    publisher_ = create_publisher<Twist>("cmd_vel", 1000);
    low_ = create_subscription<Twist>("cmd_vel_low", 1000, [this](const Twist::SharedPtr msg) {
          if (rclcpp::Clock().now() >= green_at_) {
            publisher_->publish(*msg);
          }
        });
    high_ = create_subscription<Twist>("cmd_vel_high", 1000, [this](const Twist::SharedPtr msg) {
          green_at_ = rclcpp::Clock().now() + rclcpp::Duration(10s);
          publisher_->publish(*msg);
        });
  }

private:
  rclcpp::Publisher<Twist>::SharedPtr publisher_;
  rclcpp::Subscription<Twist>::SharedPtr low_, high_;
  rclcpp::Time green_at_{0, 0, RCL_SYSTEM_TIME};
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<Multiplexer>());
  rclcpp::shutdown();
  return 0;
}
