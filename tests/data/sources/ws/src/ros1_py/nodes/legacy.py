#!/usr/bin/env python
# A Python 2 node: tree-sitter reads it all the same.
import rospy
from std_msgs.msg import *
from ros1_py.msg import *

def callback(data):
    print "heard", data.data

rospy.init_node('legacy', anonymous=True)
rospy.Subscriber("chatter", String, callback)
pub = rospy.Publisher("status", Status)
server = __import__('actionlib').SimpleActionServer
rospy.spin()
