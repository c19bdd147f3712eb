#include <rclcpp/rclcpp.hpp>
#include <rclcpp_action/rclcpp_action.hpp>
#include <nav2_msgs/action/navigate_to_pose.hpp>
#include <example_interfaces/action/fibonacci.hpp>

class Actions : public rclcpp::Node
{
public:
  using Fibonacci = example_interfaces::action::Fibonacci;
  using GoalHandle = rclcpp_action::ServerGoalHandle<Fibonacci>;

  Actions() : Node("actions")
  {
    server_ = rclcpp_action::create_server<Fibonacci>(
      this, "fibonacci",
      [](const rclcpp_action::GoalUUID &, std::shared_ptr<const Fibonacci::Goal>) {
        return rclcpp_action::GoalResponse::ACCEPT_AND_EXECUTE; },
      [](const std::shared_ptr<GoalHandle>) { return rclcpp_action::CancelResponse::ACCEPT; },
      [](const std::shared_ptr<GoalHandle>) {});
    client_ = rclcpp_action::create_client<nav2_msgs::action::NavigateToPose>(
      this->get_node_base_interface(), this->get_node_graph_interface(), this->get_node_logging_interface(),
      this->get_node_waitables_interface(), "navigate_to_pose");
  }

private:
  rclcpp_action::Server<Fibonacci>::SharedPtr server_;
  rclcpp_action::Client<nav2_msgs::action::NavigateToPose>::SharedPtr client_;
};
