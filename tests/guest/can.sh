# The CAN suite, run by the guest's init (tests/guest/init) as root in a kernel with vcan:
# brings vcan0 up and runs hal_tests' SocketCAN tests on it. iproute2's ip (copied in from the
# host) because busybox's cannot create a vcan link; called by its path because busybox's sh
# prefers its own applets to PATH.
set -e
/opt/host/ip link add dev vcan0 type vcan
/opt/host/ip link set vcan0 up
/opt/host/ip -details link show vcan0
GTEST_COLOR=no /opt/sculpt/hal_tests --gtest_filter='*CanSocket*'
