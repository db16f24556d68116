"""Distribution seams: the communicator every global reduction goes through."""

from peridynamics.parallel.communicator import SERIAL, Communicator, SerialCommunicator

__all__ = ["SERIAL", "Communicator", "SerialCommunicator"]
