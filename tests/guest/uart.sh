# The UART suite, run by the guest's init (tests/guest/init) as root: the serial backends on the
# guest's second 16550A (ttyS1; ttyS0 is the console), which scripts/guest_test.sh gives a null
# back end (the tests run it in loopback, so nothing it sends leaves the guest), and on an
# emulated FTDI USB-serial adapter (ttyUSB0) cabled to the third 16550A (ttyS2).
set -e
[ -c /dev/ttyS1 ] || { echo "uart.sh: no /dev/ttyS1"; exit 1; }
[ -c /dev/ttyS2 ] || { echo "uart.sh: no /dev/ttyS2"; exit 1; }
i=0
while [ ! -c /dev/ttyUSB0 ]; do
  i=$((i + 1))
  [ "$i" -lt 100 ] || { echo "uart.sh: the USB-serial adapter did not come up"; exit 1; }
  sleep 0.1
done
# The adapter's USB device (its `authorized` switch unplugs and plugs it in again).
PORT=$(readlink -f /sys/class/tty/ttyUSB0/device) # .../1-1/1-1:1.0/ttyUSB0
ADAPTER_USB=$(dirname "$(dirname "$PORT")")
echo "uart.sh: ttyUSB0 on $ADAPTER_USB ($(cat "$ADAPTER_USB/product" 2>/dev/null))"
GLOVE_UART=/dev/ttyS1 GLOVE_ADAPTER=/dev/ttyUSB0 GLOVE_ADAPTER_USB=$ADAPTER_USB GLOVE_ADAPTER_PEER=/dev/ttyS2 \
  GTEST_COLOR=no /opt/sculpt/guest_uart_tests
