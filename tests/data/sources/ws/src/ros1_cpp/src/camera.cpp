#include <ros/ros.h>
#include <image_transport/image_transport.h>
#include <message_filters/subscriber.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/CameraInfo.h>

void onImage(const sensor_msgs::ImageConstPtr& img) {}

class Fusion
{
public:
  Fusion(ros::NodeHandle& nh) : imu_sub_(nh, "imu/data", 10)
  {
    info_sub_.subscribe(nh, "camera/info", 5);
  }
  message_filters::Subscriber<sensor_msgs::Imu> imu_sub_;
  message_filters::Subscriber<sensor_msgs::CameraInfo> info_sub_;
};

int main(int argc, char** argv)
{
  ros::init(argc, argv, "camera");
  ros::NodeHandle nh;
  image_transport::ImageTransport it(nh);
  image_transport::Publisher pub = it.advertise("camera/image", 1);
  image_transport::Subscriber sub = it.subscribe("input/image", 1, onImage);
  image_transport::CameraPublisher cam = it.advertiseCamera("stereo/left/image_raw", 1);
  Fusion f(nh);
  return 0;
}
