import rclpy
from rclpy.action import ActionServer, ActionClient
from rclpy.node import Node
from example_interfaces.action import Fibonacci
from example_interfaces import srv


class Server(Node):
    def __init__(self):
        super().__init__('server')
        self.srv = self.create_service(srv.AddTwoInts, 'add_two_ints', self.add)
        self._action = ActionServer(self, Fibonacci, 'fibonacci', self.execute)
        self._client = ActionClient(self, Fibonacci, '/other/fibonacci')

    def add(self, req, res):
        return res

    def execute(self, goal):
        return None


def main():
    rclpy.init()
    rclpy.spin(Server())
