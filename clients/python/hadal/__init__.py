"""Python client of the Hadal deep-sea simulator.

    import hadal
    client = hadal.Client()                  # DDS domain $ROS_DOMAIN_ID, else 0 (hadal.default_domain_id())
    client.wait_for_server()
    client.set_commands("auv", [0.6, 0.0, 0.0])
    odom = client.wait_odometry("auv", min_stamp=client.step(500))   # lockstep servers
    print(odom.p_WB, odom.v_WB_B)
    client.wait_magnetic_field("auv", "magnetometer", timeout_s=0)   # sensors: subscribed on first use
    client.wait_for_subscriptions()
    mag = client.wait_magnetic_field("auv", "magnetometer", min_stamp=client.step(50))
    print(mag.magnetic_field)                                         # tesla, in the sensor frame

    frame = client.wait_image("auv", "camera", min_stamp=t)          # cameras: frame.array is (H, W, 3) uint8

    with hadal.Server("rov", mode="lockstep") as server:            # launch hadald ($ROS_DOMAIN_ID, else 0)
        with hadal.Client(domain_id=server.domain_id) as client:      # left at the end of the block
            client.reset(seed=3, poses={"rov": (0, 0, -50)})          # start over at t = 0, no restart

Recorded runs: hadal.bag.Bag(BAG_DIR).messages("/auv/odometry") -> [(t_s, Odometry)] (hadal.decode_message).

Errors: hadal.ClientError and its subclasses ServerNotFound, ScenarioError, ServerLost, Timeout,
UnknownVehicle, UnknownSensor, CommandRejected.

Set ROS_LOCALHOST_ONLY=1 (as for hadald) to keep DDS discovery on this machine.
"""

from ._hadal import (AcousticPacket, AcousticPackets, BuoyancyEngineStates, CableShape, CameraInfo, Client, DropWeightStates, Dvl, FinStates, FluidPressure,
                     Image, Imu, LaserScan, LblRange, LblRanges, MagneticField, NavSatFix, Odometry, Range, RawSonarImage, ServerMode,
                     SimStatus, SonarDetections, SonarImage, ThrusterStates, TrackStates, UsblFix, UsblFixes, SeaState, WinchState, Wrench,
                     decodable_message_types,
                     decode_message, default_domain_id)
from .errors import (ClientError, CommandRejected, ScenarioError, ServerLost, ServerNotFound, Timeout,
                     UnknownSensor, UnknownVehicle)
from . import frames
from .server import Server

__all__ = ["AcousticPacket", "AcousticPackets", "BuoyancyEngineStates", "CableShape", "CameraInfo", "Client", "ClientError", "CommandRejected", "DropWeightStates",
           "Dvl", "FinStates", "FluidPressure", "Image", "Imu", "LaserScan", "LblRange", "LblRanges", "MagneticField", "NavSatFix",
           "Odometry", "Range", "RawSonarImage", "ScenarioError", "Server", "ServerLost", "ServerMode", "ServerNotFound", "SimStatus",
           "SonarDetections", "SonarImage", "ThrusterStates", "Timeout", "TrackStates", "UnknownSensor", "UnknownVehicle",
           "UsblFix", "UsblFixes", "SeaState", "WinchState", "Wrench", "decodable_message_types", "decode_message", "default_domain_id"]
