// multiplexer (thesis Listing 2.7): forwards the high-priority commands (cmd_vel_high, from
// turtle_teleop_key) at once and holds the low-priority ones (cmd_vel_low, from
// random_controller) for ten seconds after each high-priority message.
#include "ros/ros.h"
#include "geometry_msgs/Twist.h"

ros::Publisher publisher;

ros::Timer timer;

int SEMAPHORE = 1; //decides if a message is published (1-green) or not (0-red)

void reset(const ros::TimerEvent& event){
    SEMAPHORE = 1; //the SEMAPHORE is set to green again
}

void lowCallback(const geometry_msgs::Twist& msg){
    if (SEMAPHORE) //publishes a low priority topic's message if the SEMAPHORE is green
        publisher.publish(msg);
}

void highCallback(const geometry_msgs::Twist& msg){
    SEMAPHORE = 0; //disables the publication of low priority topic messages

    timer.setPeriod(ros::Duration(10));

    timer.start(); //starts a countdown to change SEMAPHORE

    publisher.publish(msg); //publishes the message
}

int main(int argc, char **argv){
    ros::init(argc, argv, "multiplexer");

    ros::NodeHandle n;

    ros::Subscriber low_subscriber, high_subscriber;

    timer = n.createTimer(ros::Duration(10), reset, true);

    publisher = n.advertise<geometry_msgs::Twist>("cmd_vel", 1000);

    low_subscriber = n.subscribe("cmd_vel_low", 1000, lowCallback); //low priority topic subscription

    high_subscriber = n.subscribe("cmd_vel_high", 1000, highCallback); //high priority topic subscription

    ros::spin();

    return 0;
}
