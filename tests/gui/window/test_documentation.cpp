// Help > Documentation (F1) and Help > Keyboard shortcuts: the guide shown
// in the window from the README with its links between pages followed in
// place; the shortcut table listing every menu entry that has a key.
#include <QAction>
#include <QMainWindow>
#include <QMenu>
#include <QMenuBar>
#include <QTextBlock>
#include <QTextBrowser>
#include <QUndoStack>
#include <QtTest>
#include <filesystem>

#include "gui/window/documentation.h"
#include "gui/window/window_menus.h"

using namespace linkscape::gui;

class DocumentationTest : public QObject {
  Q_OBJECT
 private slots:
  void guideOpensAtTheReadmeAndFollowsItsLinks() {
    const std::filesystem::path home = documentation_home();
    QVERIFY2(!home.empty(), "no README.md beside the program or in its source tree");
    QCOMPARE(QString::fromStdString(home.filename().string()), QString("README.md"));
    DocumentationBrowser dialog(home);
    QTextBrowser* browser = dialog.browser();
    // Rendered as Markdown: the heading is a title, not "# Linkscape".
    QVERIFY(browser->toPlainText().startsWith("Linkscape"));
    QVERIFY(browser->toPlainText().contains("Quick start"));
    // Its screenshots fit the page's width.
    int images = 0;
    for (QTextBlock block = browser->document()->begin(); block.isValid(); block = block.next())
      for (auto it = block.begin(); !it.atEnd(); ++it)
        if (const QTextImageFormat image = it.fragment().charFormat().toImageFormat(); image.isValid()) {
          ++images;
          QVERIFY2(image.width() > 0 && image.width() <= 760, qPrintable(image.name()));
        }
    QVERIFY(images > 0);
    // A link of the README's to a page in docs/ opens that page in place.
    browser->setSource(QUrl("docs/architecture.md"));
    QVERIFY2(browser->source().toString().endsWith("docs/architecture.md"), qPrintable(browser->source().toString()));
    QVERIFY(browser->toPlainText().startsWith("Architecture"));
    QVERIFY(browser->toPlainText().contains("Folder map"));
    QVERIFY(browser->isBackwardAvailable());
    browser->backward();
    QVERIFY(browser->source().toLocalFile().endsWith("README.md"));
  }

  void shortcutTableListsEveryMenuKey() {
    const auto window = window_with_menus();
    const QString table = shortcut_table(window->menuBar());
    // Every entry with a key is a row, by its menu path, with the key as the desktop writes it.
    int keyed = 0;
    std::function<void(const QMenu*)> count = [&](const QMenu* menu) {
      for (const QAction* a : menu->actions()) {
        if (a->menu()) count(a->menu());
        else if (!a->shortcut().isEmpty()) {
          ++keyed;
          QVERIFY2(table.contains(a->text().remove('&')), qPrintable(a->text()));
          QVERIFY2(table.contains(a->shortcut().toString(QKeySequence::NativeText)), qPrintable(a->text()));
        }
      }
    };
    for (const QAction* a : window->menuBar()->actions())
      if (a->menu()) count(a->menu());
    QCOMPARE(table.count('\n'), keyed);
    QVERIFY(table.contains(QRegularExpression("Help > Documentation +F1\n")));
    QVERIFY(table.contains(QRegularExpression("File > Quit +Ctrl\\+Q\n")));
  }
};

QTEST_MAIN(DocumentationTest)
#include "test_documentation.moc"
