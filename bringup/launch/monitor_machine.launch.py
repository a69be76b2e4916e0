"""The monitor beside a real machine's DDS bridge: it watches the bridge's sensor_msgs/JointState
and publishes `monitor/status` and /diagnostics; optionally the recorder keeps a bag of it all.

    ros2 launch fiveaxis_bringup monitor_machine.launch.py joint_states:=/joint_states \
        machine:=hermle-c600u axis_map:=X=joint_0,Y=joint_1,Z=joint_2,A=joint_3,C=joint_4 \
        namespace:=/cell1 program:=part.ngc bag:=shift_bag

`axis_map` gives the bridge's joint name for each machine axis (comma-separated AXIS=JOINT; empty:
the joints are named as the axes). A machine read through MTConnect needs no ROS bridge of its own:
`mtconnect_agent:=http://agent:5000` starts fiveaxis-bridge on the agent (`mtconnect_device:=NAME`
where it serves several), which publishes the axes on `machine/joint_states` for the monitor; then
`axis_map` names the agent's data items (AXIS=ID, empty: the axis components of the same names).
`opcua_server:=opc.tcp://cnc:4840` does the same for a control's OPC UA server with the OPC 40502
CNC model (`axis_map` then names its CncAxis objects). `program` (optional) is the NC program the machine runs, for the
programmed feed and the work offset; `work_offset_mm` (X,Y,Z) is the control's active datum when no
program is given. The machine's own clock stamps its states: `use_sim_time` stays false.
"""
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, GroupAction, OpaqueFunction
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node, PushRosNamespace


def node(name, **kwargs):
    """Node `name` (commander, simulator, monitor, recorder): ROS package fiveaxis_NAME installs
    executable fiveaxis-NAME (nodes/NAME/package.xml)."""
    return Node(package=f"fiveaxis_{name}", executable=f"fiveaxis-{name}", name=f"fiveaxis_{name}",
                output="screen", **kwargs)


def nodes(context):
    """The monitor (and the recorder when `bag` is given), with the optional settings only when set:
    a ROS parameter cannot be declared empty."""
    arg = lambda name: LaunchConfiguration(name).perform(context).strip()
    joint_states = arg("joint_states")
    axis_map = [m.strip() for m in arg("axis_map").split(",") if m.strip()]
    actions = [PushRosNamespace(arg("namespace"))]
    if arg("mtconnect_agent") or arg("opcua_server"):
        # The bridge reads the agent or the server; its JointState names the joints as the machine's
        # axes.
        bridge = {"machine": arg("machine")}
        for name in ("mtconnect_agent", "mtconnect_device", "opcua_server"):
            if arg(name):
                bridge[name] = arg(name)
        if axis_map:
            bridge["axis_map"] = axis_map
        actions.append(node("bridge", parameters=[bridge]))
        joint_states, axis_map = "machine/joint_states", []
    monitor = {"machine": arg("machine"), "joint_state_input": [joint_states], "lookahead": ""}
    if axis_map:
        monitor["axis_map"] = axis_map
    for name in ("program", "work_offset_mm"):
        if arg(name):
            monitor[name] = arg(name)
    actions.append(node("monitor", parameters=[monitor]))
    if arg("bag"):
        actions.append(node("recorder", parameters=[{"machine": arg("machine"), "output": arg("bag"),
                                                     "topic": [joint_states + ":JointState",
                                                               "monitor/status:SingularityStatus",
                                                               "/diagnostics:DiagnosticArray"]}]))
    return [GroupAction(actions)]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument("joint_states", default_value="/joint_states",
                              description="the bridge's sensor_msgs/JointState topic"),
        DeclareLaunchArgument("machine", default_value="hermle-c600u",
                              description="built-in machine name, or a TOML or URDF machine file"),
        DeclareLaunchArgument("axis_map", default_value="",
                              description="AXIS=JOINT,... the bridge's joint names (empty: as the axes)"),
        DeclareLaunchArgument("namespace", default_value="/fiveaxis",
                              description="namespace of the monitor and its topics"),
        DeclareLaunchArgument("program", default_value="",
                              description="the NC program the machine runs (optional)"),
        DeclareLaunchArgument("work_offset_mm", default_value="",
                              description="the control's active work offset X,Y,Z in mm, without a program"),
        DeclareLaunchArgument("mtconnect_agent", default_value="",
                              description="an MTConnect agent's URL: read the machine from it (starts fiveaxis-bridge)"),
        DeclareLaunchArgument("mtconnect_device", default_value="",
                              description="the agent's device (name or uuid) where it serves several"),
        DeclareLaunchArgument("opcua_server", default_value="",
                              description="an OPC UA server's URL (opc.tcp://...): read the machine's OPC 40502 CNC model (starts fiveaxis-bridge)"),
        DeclareLaunchArgument("bag", default_value="",
                              description="also record the joint states, status and diagnostics to this bag"),
        OpaqueFunction(function=nodes),
    ])
