#pragma once
#include <string>
#include <std_msgs/String.h>

#define STATUS_TOPIC "status"
namespace ros1_cpp {
static const std::string kPrefix = "robot";
constexpr char kDiagnostics[] = "/diagnostics_agg";
typedef std_msgs::String Text;
using Count = std_msgs::Int32;
}
