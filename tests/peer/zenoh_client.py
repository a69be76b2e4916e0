"""The Zenoh client configuration the fleet's Python peers share (Eclipse Zenoh's Python API): a
client of the one router named, no multicast scouting (the fleet is what the endpoints join), and
for a tls/ endpoint the CA to trust (no client certificate is presented)."""
import json

import zenoh


def client_config(connect, root_ca=None):
    conf = zenoh.Config()
    if root_ca:
        conf.insert_json5("transport/link/tls/root_ca_certificate", json.dumps(root_ca))
    conf.insert_json5("mode", '"client"')
    conf.insert_json5("connect/endpoints", json.dumps([connect]))
    conf.insert_json5("scouting/multicast/enabled", "false")
    return conf
