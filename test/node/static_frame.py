#!/usr/bin/python3
"""A static transform on /tf_static, as tf2_ros's static_transform_publisher
gives it (Debian's ROS packages ship the library, not that executable):
    static_frame.py X Y Z YAW PITCH ROLL PARENT CHILD
metres and radians; the rotation is Rz(yaw) Ry(pitch) Rx(roll), the URDF's
rpy convention. The rostests use it for a camera frame that exists only in
TF (a calibration), not in the rig's URDF."""

import math
import sys

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped


def quaternion(yaw, pitch, roll):
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def main():
    args = rospy.myargv(sys.argv)[1:]
    if len(args) != 8:
        sys.exit('usage: static_frame.py X Y Z YAW PITCH ROLL PARENT CHILD')
    x, y, z, yaw, pitch, roll = (float(a) for a in args[:6])
    rospy.init_node('static_frame', anonymous=True)
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id, t.child_frame_id = args[6], args[7]
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = x, y, z
    q = quaternion(yaw, pitch, roll)
    (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
     t.transform.rotation.w) = q
    tf2_ros.StaticTransformBroadcaster().sendTransform(t)
    rospy.spin()


if __name__ == '__main__':
    main()
