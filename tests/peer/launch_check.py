#!/usr/bin/env python3
"""What a ROS 2 launch file would start, without ROS: the launch file is executed with small
recording stand-ins for the `launch` and `launch_ros` modules (ROS 2's own are not on PyPI), its
launch arguments at their defaults (or KEY=VALUE overrides), OpaqueFunctions called with them.

usage: launch_check.py FILE.launch.py [KEY=VALUE ...]
Prints JSON: {"arguments": {name: default}, "nodes": [{"package", "executable", "name",
"namespace", "parameters": {name: value}}]}. Only what the fiveaxis launch files use is modelled:
DeclareLaunchArgument, LaunchConfiguration, GroupAction, PushRosNamespace, OpaqueFunction, Node.
"""
import importlib.util
import json
import sys
import types


class LaunchConfiguration:
    def __init__(self, name):
        self.name = name

    def perform(self, context):
        return context["args"][self.name]


class DeclareLaunchArgument:
    def __init__(self, name, default_value=None, description=""):
        self.name, self.default = name, default_value


class GroupAction:
    def __init__(self, actions):
        self.actions = actions


class PushRosNamespace:
    def __init__(self, namespace):
        self.namespace = namespace


class OpaqueFunction:
    def __init__(self, function):
        self.function = function


class Node:
    def __init__(self, package, executable, name=None, namespace=None, parameters=(), output=None, **rest):
        self.package, self.executable, self.name, self.namespace, self.parameters = package, executable, name, namespace, parameters


class LaunchDescription:
    def __init__(self, entities):
        self.entities = entities


def value(v, context):
    """A parameter value as launch_ros passes it: substitutions performed, then read as YAML."""
    if isinstance(v, LaunchConfiguration):
        from ruamel.yaml import YAML  # rosbags' YAML library, installed by launch-free-scripts/test
        return YAML(typ="safe").load(v.perform(context))
    if isinstance(v, list):
        return [value(x, context) for x in v]
    return v


def walk(entities, context, namespace, out):
    for e in entities:
        if isinstance(e, GroupAction):
            walk(e.actions, context, namespace, out)
        elif isinstance(e, PushRosNamespace):
            ns = e.namespace.perform(context) if isinstance(e.namespace, LaunchConfiguration) else e.namespace
            namespace = ns if ns.startswith("/") else namespace.rstrip("/") + "/" + ns
        elif isinstance(e, OpaqueFunction):
            walk(e.function(context), context, namespace, out)
        elif isinstance(e, Node):
            params = {}
            for d in e.parameters:
                params.update({k: value(v, context) for k, v in d.items()})
            out.append({"package": e.package, "executable": e.executable, "name": e.name,
                        "namespace": namespace, "parameters": params})


def main():
    launch = types.ModuleType("launch")
    launch.LaunchDescription = LaunchDescription
    actions = types.ModuleType("launch.actions")
    actions.DeclareLaunchArgument, actions.GroupAction, actions.OpaqueFunction = DeclareLaunchArgument, GroupAction, OpaqueFunction
    subs = types.ModuleType("launch.substitutions")
    subs.LaunchConfiguration = LaunchConfiguration
    ros = types.ModuleType("launch_ros")
    ros_actions = types.ModuleType("launch_ros.actions")
    ros_actions.Node, ros_actions.PushRosNamespace = Node, PushRosNamespace
    sys.modules.update({"launch": launch, "launch.actions": actions, "launch.substitutions": subs,
                        "launch_ros": ros, "launch_ros.actions": ros_actions})
    spec = importlib.util.spec_from_file_location("launch_file", sys.argv[1])
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    ld = mod.generate_launch_description()
    args = {e.name: e.default for e in ld.entities if isinstance(e, DeclareLaunchArgument)}
    for kv in sys.argv[2:]:
        k, _, v = kv.partition("=")
        if k not in args:
            sys.exit(f"{k} is not a launch argument of {sys.argv[1]} (its arguments: {', '.join(args)})")
        args[k] = v
    nodes = []
    walk(ld.entities, {"args": args}, "/", nodes)
    print(json.dumps({"arguments": {e.name: e.default for e in ld.entities if isinstance(e, DeclareLaunchArgument)}, "nodes": nodes}))


if __name__ == "__main__":
    main()
