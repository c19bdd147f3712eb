// random_controller in ROS 2 (the thesis's Listing 2.4, with rclcpp): Twist messages with a
// random angular velocity at 5 Hz; the linear velocity is the node's parameter `vel`.
#include <cmath>
#include <memory>
#include <random>

#include "geometry_msgs/msg/twist.hpp"
#include "rclcpp/rclcpp.hpp"

class RandomController : public rclcpp::Node
{
public:
  RandomController()
  : Node("random_controller")
  {
    vel_ = declare_parameter("vel", 0.0);
    publisher_ = create_publisher<geometry_msgs::msg::Twist>("cmd_vel", 1000);
    timer_ = create_wall_timer(std::chrono::milliseconds(200), [this]() {
        geometry_msgs::msg::Twist msg;
        msg.linear.x = vel_;
        msg.angular.z = (double(rand()) / double(RAND_MAX)) * 2 * M_PI - M_PI;
        publisher_->publish(msg);
      });
  }

private:
  double vel_;
  rclcpp::Publisher<geometry_msgs::msg::Twist>::SharedPtr publisher_;
  rclcpp::TimerBase::SharedPtr timer_;
};

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  rclcpp::spin(std::make_shared<RandomController>());
  rclcpp::shutdown();
  return 0;
}
