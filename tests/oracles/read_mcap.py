"""Reads an MCAP recording with the `mcap` package from PyPI (Foxglove's reader) and prints
every message as JSON: topic, schema name and encoding, message encoding, log time, the decoded
JSON body, and for foxglove.PointCloud the points unpacked from base64 by `point_stride`/`fields`.
Usage: python read_mcap.py FILE.mcap"""
import base64
import json
import struct
import sys

from mcap.reader import make_reader

out = []
with open(sys.argv[1], "rb") as f:
    reader = make_reader(f)
    for schema, channel, message in reader.iter_messages():
        body = json.loads(message.data)
        entry = {
            "topic": channel.topic,
            "schema": schema.name,
            "schema_encoding": schema.encoding,
            "message_encoding": channel.message_encoding,
            "log_time": message.log_time,
            "body": body,
        }
        if schema.name == "foxglove.PointCloud":
            raw = base64.b64decode(body["data"])
            stride = body["point_stride"]
            fields = sorted(body["fields"], key=lambda fl: fl["offset"])
            assert all(fl["type"] == 7 for fl in fields), "FLOAT32 fields expected"
            entry["points"] = [
                [struct.unpack_from("<f", raw, i + fl["offset"])[0] for fl in fields]
                for i in range(0, len(raw), stride)
            ]
            del entry["body"]["data"]
        out.append(entry)
json.dump(out, sys.stdout)
