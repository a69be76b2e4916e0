"""The fiveaxis node set on one NC program: monitor, recorder, simulator and commander.

    ros2 launch fiveaxis_bringup node_set.launch.py program:=bundled:SING.I machine:=hermle-c600u \
        namespace:=/cell1 bag:=sing_bag speed:=1.0 use_sim_time:=true

Every node runs in `namespace` (topics `commanded/axis_state`, `simulated/axis_state`,
`monitor/status`, ...), on the same `machine` and the same clock: with `use_sim_time` (the default
here) every message carries program time and the commander publishes it on /clock; without it wall
time, and `speed` must then be 1. The commander and simulator wait for their two subscribers
(monitor and recorder) before the first sample, so nothing is lost. Settings are ROS parameters of
the same names as the nodes' flags (`<executable> --help` lists them).
"""
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace


def node(name, **kwargs):
    """Node `name` (commander, simulator, monitor, recorder): ROS package fiveaxis_NAME installs
    executable fiveaxis-NAME (nodes/NAME/package.xml)."""
    return Node(package=f"fiveaxis_{name}", executable=f"fiveaxis-{name}", name=f"fiveaxis_{name}",
                output="screen", **kwargs)


def generate_launch_description():
    program = LaunchConfiguration("program")
    machine = LaunchConfiguration("machine")
    use_sim_time = LaunchConfiguration("use_sim_time")
    speed = LaunchConfiguration("speed")
    bag = LaunchConfiguration("bag")
    common = {"machine": machine, "use_sim_time": use_sim_time}
    publisher = {**common, "program": program, "speed": speed, "min_subscribers": 2}
    return LaunchDescription([
        DeclareLaunchArgument("program", default_value="bundled:SING.I",
                              description="NC or CL program: a file, builtin:NAME or bundled:NAME"),
        DeclareLaunchArgument("machine", default_value="hermle-c600u",
                              description="built-in machine name, or a TOML or URDF machine file"),
        DeclareLaunchArgument("namespace", default_value="/fiveaxis",
                              description="namespace of the nodes and their topics"),
        DeclareLaunchArgument("use_sim_time", default_value="true",
                              description="stamp in program time and publish /clock (else wall time, speed 1)"),
        DeclareLaunchArgument("speed", default_value="1.0",
                              description="real-time factor of commander and simulator"),
        DeclareLaunchArgument("bag", default_value="fiveaxis_bag",
                              description="rosbag2 directory the recorder writes (must not exist)"),
        GroupAction([
            PushRosNamespace(LaunchConfiguration("namespace")),
            node("monitor", parameters=[common]),
            node("recorder", parameters=[{**common, "output": bag}]),
            node("simulator", parameters=[publisher]),
            node("commander", parameters=[publisher]),
        ]),
    ])
