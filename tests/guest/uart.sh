# The UART suite, run by the guest's init (tests/guest/init) as root: the serial haptic sink on
# the guest's second 16550A (ttyS1; ttyS0 is the console), which scripts/guest_test.sh gives a
# null back end: the tests run the UART in loopback, so nothing it sends leaves the guest.
set -e
[ -c /dev/ttyS1 ] || { echo "uart.sh: no /dev/ttyS1"; exit 1; }
GLOVE_UART=/dev/ttyS1 GTEST_COLOR=no /opt/sculpt/guest_uart_tests
