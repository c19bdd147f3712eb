// random_controller (thesis Listing 2.4): sends turtleX consecutive Twist messages with a
// random angular velocity, making it move randomly; the linear velocity comes from the
// parameter `vel`.
#include "ros/ros.h"
#include "geometry_msgs/Twist.h"
#include <random>
#include <cmath>

int main(int argc, char **argv){
    ros::init(argc, argv, "random_controller");

    ros::NodeHandle n;

    ros::Publisher publisher = n.advertise<geometry_msgs::Twist>("cmd_vel", 1000);

    geometry_msgs::Twist msg; //initializes a Twist message with all values to zero

    ros::Rate loop_rate(5); //loops at a 5Hz rate

    n.getParam("vel", msg.linear.x); //x component of linear vector is set to vel parameter value

    while(ros::ok()){ //loops as long as ros is running
        msg.angular.z = ((double(rand()) / double(RAND_MAX)) * (M_PI - (-M_PI)))
                        + (-M_PI); //z component set to a random value between -pi and pi

        publisher.publish(msg); //publishes the message

        loop_rate.sleep();
    }

    return 0;
}
