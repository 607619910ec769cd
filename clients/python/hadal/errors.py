"""The errors of the hadal package. Every one is a ClientError (a RuntimeError), so `except
hadal.ClientError` catches them all; the subclasses say what went wrong.

    try:
        client.step(10)
    except hadal.CommandRejected as e:
        print("the server said:", e.reason)
"""


class ClientError(RuntimeError):
    """An error of the Hadal client."""


class ServerNotFound(ClientError):
    """No server: hadald could not be found or started, did not come up, or no lockstep server answers on
    the client's DDS domain."""


class ScenarioError(ClientError, ValueError):
    """hadald refused the scenario before anything started; `errors` are its lines
    ("file:line:col: error: <path>: <what is wrong>"), `scenario` the file given. Also a builtin ValueError."""

    def __init__(self, scenario, errors):
        super().__init__(f"{scenario}: {len(errors)} error(s) in the scenario:\n" + "\n".join(errors))
        self.scenario = scenario
        self.errors = list(errors)


class ServerLost(ClientError, ConnectionError):
    """The server went silent (no status heartbeat within the client's server_timeout_s) while a request
    waited for its reply: it stopped, crashed, or the link is down; the request is lost. Once a server
    publishes again (client.wait_for_server()), the same client works again. Also a builtin ConnectionError."""


class Timeout(ClientError, TimeoutError):
    """The server did not reply in time (also a builtin TimeoutError)."""


class UnknownVehicle(ClientError, KeyError):
    """A vehicle the server does not have; `vehicle` is its name."""

    def __init__(self, message, vehicle=None):
        super().__init__(message)
        self.vehicle = vehicle

    def __str__(self):  # KeyError would quote the message
        return RuntimeError.__str__(self)


class UnknownSensor(ClientError, KeyError):
    """A sensor the vehicle does not have, or has as another type than the call reads (wait_imu on a DVL);
    `vehicle` and `sensor` name it, the message lists the vehicle's sensors and their types."""

    def __init__(self, message, vehicle=None, sensor=None):
        super().__init__(message)
        self.vehicle = vehicle
        self.sensor = sensor

    def __str__(self):  # KeyError would quote the message
        return RuntimeError.__str__(self)


class CommandRejected(ClientError):
    """The server refused a request (a wrong number of setpoints, NaN, a value out of range, a malformed
    reset); `reason` is the server's own words."""

    def __init__(self, message, reason=None):
        super().__init__(message)
        self.reason = reason if reason is not None else message
