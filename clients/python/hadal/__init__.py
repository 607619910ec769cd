"""Python client of the Hadal deep-sea simulator.

    import hadal
    client = hadal.Client(domain_id=0)
    client.wait_for_server()
    client.set_thrusters("auv", [0.6, 0.0, 0.0])
    odom = client.wait_odometry("auv", min_stamp=client.step(500))   # lockstep servers
    print(odom.p_WB, odom.v_WB_B)

Set ROS_LOCALHOST_ONLY=1 (as for hadald) to keep DDS discovery on this machine.
"""

from ._hadal import Client, ClientError, Odometry, ServerMode, SimStatus, ThrusterStates

__all__ = ["Client", "ClientError", "Odometry", "ServerMode", "SimStatus", "ThrusterStates"]
