"""A VectorEnv worker (hadal/env.py): one HadalEnv in this process, driven by pickled (command, payload)
messages on stdin, answered with pickled ("ok", result) or ("error", exception) on stdout. Ends (closing the
env and so stopping its server) on "close" or when stdin closes, e.g. because the parent died."""

import pickle
import sys

import numpy as np


def main():
    requests, replies = sys.stdin.buffer, sys.stdout.buffer
    sys.stdout = sys.stderr  # nothing else may write to the reply pipe
    from hadal.env import HadalEnv, step_with_autoreset
    env = None
    try:
        while True:
            try:
                command, payload = pickle.load(requests)
            except EOFError:
                break
            try:
                if command == "make":
                    env = HadalEnv(**payload)
                    result = (env.observation_space.shape, env.action_space.shape, env.domain_id)
                elif command == "reset":
                    result = env.reset(seed=payload[0], options=payload[1])
                elif command == "step":
                    action, autoreset = payload
                    result = step_with_autoreset(env, np.asarray(action), autoreset)
                elif command == "close":
                    result = None
                else:
                    raise ValueError(f"unknown VectorEnv command {command!r}")
                reply = ("ok", result)
            except Exception as error:  # reported to the parent, which raises it
                reply = ("error", error)
            replies.write(pickle.dumps(reply, protocol=pickle.HIGHEST_PROTOCOL))  # one write: stdout may be
            replies.flush()                                                       # unbuffered (python -u)
            if command == "close":
                break
    finally:
        if env is not None:
            env.close()


if __name__ == "__main__":
    main()
