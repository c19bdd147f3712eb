#include <rclcpp/rclcpp.hpp>
#include <std_msgs/msg/string.hpp>

using std_msgs::msg::String;
static const char TOPIC[] = "chatter";

int main(int argc, char ** argv)
{
  rclcpp::init(argc, argv);
  auto node = rclcpp::Node::make_shared("minimal");
  auto pub = node->create_publisher<String>(std::string(TOPIC) + "_out", 10);
  auto on_msg = [](const String::SharedPtr msg) {};
  auto sub = node->create_subscription<String>(TOPIC, 10, on_msg);
  auto raw = node->create_generic_publisher("raw", "std_msgs/msg/UInt8", 10);
  rclcpp::spin(node);
  return 0;
}
