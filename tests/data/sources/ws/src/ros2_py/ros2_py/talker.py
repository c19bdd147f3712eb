import rclpy
from rclpy.node import Node
from std_msgs.msg import String
from example_interfaces.srv import AddTwoInts
from .names import CHATTER


class Talker(Node):

    def __init__(self, topic=CHATTER):
        super().__init__('talker')
        self.declare_parameter('period', 0.5)
        self.declare_parameters(namespace='limits', parameters=[('max', 10), ('min', 0)])
        self.pub = self.create_publisher(String, topic, 10)
        self.sub = self.create_subscription(msg_type=String, topic='echo', callback=self.on_echo, qos_profile=10)
        self.cli = self.create_client(AddTwoInts, 'add_two_ints')
        period = self.get_parameter('period').value

    def on_echo(self, msg):
        pass


def main():
    rclpy.init()
    rclpy.spin(Talker())
