"""What PyPI's mcap reader gets from a recording that may be cut (a kill -9): its seeking reader
refuses a file without a footer, so the stream reader reads it from the start, and stops at the
first damaged record (a torn chunk fails its CRC). Shared by mcap_peer_test.py and record_test.py."""
import struct

from mcap.exceptions import McapError
from mcap.records import Channel, Message
from mcap.stream_reader import StreamReader


def messages_up_to_the_cut(path):
    """(topic, log_time, data) of every message before the first damaged record."""
    topics, out = {}, []
    with open(path, "rb") as f:
        try:
            for r in StreamReader(f, validate_crcs=True).records:
                if isinstance(r, Channel):
                    topics[r.id] = r.topic
                elif isinstance(r, Message):
                    out.append((topics[r.channel_id], r.log_time, r.data))
        except (McapError, struct.error):  # EndOfFile, CRCValidationError, a torn header
            pass
    return out
