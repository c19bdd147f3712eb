#include <rclcpp/rclcpp.hpp>
#include <sensor_msgs/msg/laser_scan.hpp>
#include <image_transport/image_transport.hpp>

namespace ros2_cpp
{
class Filter : public rclcpp::Node
{
public:
  explicit Filter(const rclcpp::NodeOptions & options)
  : Node("filter", options)
  {
    // no template argument: the type is the lambda's parameter's
    sub_ = create_subscription<sensor_msgs::msg::LaserScan>("scan", 10,
      [this](sensor_msgs::msg::LaserScan::ConstSharedPtr scan) { pub_->publish(*scan); });
    pub_ = create_publisher<sensor_msgs::msg::LaserScan>("scan_filtered", 10);
    image_pub_ = image_transport::create_publisher(this, "debug/image");
  }

private:
  rclcpp::Subscription<sensor_msgs::msg::LaserScan>::SharedPtr sub_;
  rclcpp::Publisher<sensor_msgs::msg::LaserScan>::SharedPtr pub_;
  image_transport::Publisher image_pub_;
};
}  // namespace ros2_cpp

#include "rclcpp_components/register_node_macro.hpp"
RCLCPP_COMPONENTS_REGISTER_NODE(ros2_cpp::Filter)
