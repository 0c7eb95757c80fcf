"""A plain node using its own interface package (demo_interfaces): an action `fib` and a service
`toggle`, as a package generator's Python template writes them."""
import rclpy
from rclpy.action import ActionServer
from rclpy.node import Node

from demo_interfaces.action import Fib
from demo_interfaces.srv import Toggle


class Demo(Node):
    def __init__(self):
        super().__init__("demo")
        ActionServer(self, Fib, "fib", self.execute)
        self.create_service(Toggle, "toggle", self.toggle)

    def execute(self, goal):
        sequence = [0, 1][:max(goal.request.order, 0)]
        goal.succeed()
        return Fib.Result(sequence=sequence)

    def toggle(self, request, response):
        response.success, response.message = True, f"data {request.data}"
        return response


def main():
    rclpy.init()
    try:
        rclpy.spin(Demo())
    except (KeyboardInterrupt, rclpy.executors.ExternalShutdownException):
        pass


if __name__ == "__main__":
    main()
