import rclpy
from rclpy.node import Node
from sensor_msgs.msg import Image
import message_filters


def main():
    rclpy.init()
    node = Node('watcher')
    left = message_filters.Subscriber(node, Image, 'left/image')
    # a half-edited line: the rest of the file is still read
    right = node.create_subscription(Image, 'right/image', lambda m: None,
    node.create_publisher(Image, 'merged', 10)
    rclpy.spin(node)


def other():
    node = Node('other')
    node.create_publisher(Image, 'after', 10)
