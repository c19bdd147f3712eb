import rospy
from geometry_msgs.msg import Twist
import std_msgs.msg
from ros1_py.msg import Status
from ros1_py.topics import CMD_TOPIC, NAMESPACE


class Driver(object):
    """The part of the controller node that talks to the base (a node spread over modules)."""

    def __init__(self, prefix):
        self.prefix = prefix
        self.cmd_pub = rospy.Publisher(CMD_TOPIC, Twist, queue_size=1)
        self.status_pub = rospy.Publisher(NAMESPACE + '/status', Status, queue_size=1)
        self.mode_pub = rospy.Publisher('%s/mode' % self.prefix, std_msgs.msg.String, queue_size=1)
        self.odom_sub = rospy.Subscriber('odom', std_msgs.msg.Float64, self.on_odom)

    def on_odom(self, msg):
        pass
